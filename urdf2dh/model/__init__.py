"""The kinematic model every SOURCE becomes and every table is checked against.

* :mod:`.poe`: the product-of-exponentials model (:class:`~.poe.PoeModel`, :class:`~.poe.Joint`):
  a serial chain's screws at the home pose and the tip's home pose;
* :mod:`.mimic`: joints that follow others, and the positions of a chain's every joint;
* :mod:`.fk`: the one reference forward kinematics of chains in link form (a model's, a
  table's), and :mod:`._fastfk`, its fast path for large batches.

Nothing is imported here (the modules need numpy; the command line's ``--help`` does not).
"""

__all__: list[str] = []
