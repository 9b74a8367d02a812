"""Looking at the cell: Meshcat views and replays, screenshots, the frame tree.

Lives here: ``meshcat`` (views, recordings, frusta, detection markers),
``browser`` (headless chromium screenshots of replays), ``tree`` (``view_frames``).

May import: ``omtp_drake.sim``, ``omtp_drake.control`` and everything below them.
"""
