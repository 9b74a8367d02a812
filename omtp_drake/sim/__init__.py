"""Running the cell: what changes while it runs, between and across advances.

Lives here: the driver and its world edits (``driver``), the part pool (``pool``),
the runtime with the course's services and fault injection (``runtime``), the
ledger of where every part is (``ledger``) and tf2's buffer with history (``tf``).

May import: ``omtp_drake.cell`` and everything below it (scenario, errors, assets).
"""
