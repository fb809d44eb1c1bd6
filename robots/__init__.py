"""Robot models bundled with urdf2dh (installed as the ``urdf2dh.robots`` package data)."""
