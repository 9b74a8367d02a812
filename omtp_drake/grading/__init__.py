"""Grading a class: every script (or FlexBE behaviour) of a folder run by ``ros-run``
(``flexbe-run``) on a scenario, each isolated, one verdict per run: an application on
top of :mod:`omtp_drake.ros`.

    omtp-drake grade submissions/ --scenario lecture6_assignment4

Modules, one job each:

- ``grade``: ``grade``: every script of a folder run on a scenario, isolated
- ``flexbe``: ``grade --flexbe``: a class's FlexBE behaviours, one workspace each
- ``options``: the ``ros-run`` options ``grade`` passes on (``grade.yaml``)
- ``table``: a grade's results: the printed table, ``grades.csv``, ``grades.png``, JSONs
- ``isolation``: one untrusted ``ros-run`` isolated: its folder copy, limits, sandbox
- ``guard``: the first code of an isolated run: resource limits and its write/network guard
- ``verdicts``: a graded run's verdict, named for what happened
- ``cli``: the ``grade`` command and ``ros-run``'s isolation flags (``--sandbox``)
"""
