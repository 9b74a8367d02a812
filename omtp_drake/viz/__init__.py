"""Looking at the cell: Meshcat views and replays, screenshots, the frame tree.

Modules (one job each):

- ``meshcat``: live views, recordings, frusta and detection markers in Meshcat
- ``browser``: headless chromium screenshots of standalone replays
- ``browser_host``: the process's one headless chromium, on a thread of its own, kept between screenshots
- ``tree``: the frame tree as a picture (``view_frames``)
- ``view_command``: the ``omtp-drake view`` command line
- ``model_view``: ``omtp-drake view``: a description file's model with joint sliders, sensor images and points

May import: ``omtp_drake.sim``, ``omtp_drake.control`` and everything below them.
"""
