"""The cell: what the factory is made of, as Drake systems and models.

Lives here: the station (``station.build_station``: the whole cell as one diagram; its
models in a plant: ``cell_models``),
the UR arms and their servo (``arms``), belt and break beam (``conveyor``), part
poses (``parts``), named frames (``frames``) and stamped poses (``poses``), the
logical camera (``logical_camera``; its images in ``camera_image``, the models it
may report in ``camera_candidates``, its frustum test in ``frustum``, the geometries
and boxes of bodies in ``body_geometry``, their 26-DOPs in ``kdop``, its occlusion in
``occlusion``), the RGB-D view (``rgbd``), the vacuum gripper's attach rule
(``suction``, what touches the cup in ``suction_touch``), its two holds (``suction_holds``,
the weld's constraints in ``suction_constraints``) and its test rig (``suction_rig``).

May import: ``omtp_drake.scenario``, ``omtp_drake.errors``, ``omtp_drake.assets``.
"""
