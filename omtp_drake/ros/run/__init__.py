"""``ros-run``: an unmodified course script on a cell, in simulated time.

Modules, one concept each:

- ``runner``: ``ros-run``: an unmodified course script on a cell, in simulated time
- ``bring_up``: a run's cell and ROS session from its options, alike for ros-run and flexbe-run
- ``environment``: the shims first on sys.path, sys.argv and the ROS module names, for a run only
- ``report``: the report of one ``ros-run``: times, ledger, collisions, the script's exception
- ``cli``: the ``ros-run`` command
- ``command``: what the ROS commands share: output lines, log levels, passed-on options
- ``setup_steps``: the slides' set-up steps before a script (``--call``, ``--settle``)
- ``settling``: after a run, the cell runs on until its parts rest (``--settle-after``)
- ``py2``: course code written for Melodic's Python 2.7
"""
