"""omtp_drake's own ``launch_ros`` (``Node``, ``FindPackageShare``, ``ParameterValue``), for
the launch files :mod:`omtp_drake.launch.launch_py` reads (on ``sys.path`` only then)."""
