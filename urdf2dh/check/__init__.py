"""Looking at what urdf2dh makes, from outside: against Pinocchio, against another model, against
the papers.

* :mod:`.verify`: every convention's table and the POE model against Pinocchio's forward
  kinematics, the independent oracle (the only module that imports Pinocchio);
* :mod:`.diff`: two parameter sets side by side (calibration: nominal and actual);
* :mod:`.info`: what a SOURCE holds, its chain, and how many parameters calibration can identify;
* :mod:`.papers`: the seed papers' published tables, cell by cell.

Nothing is imported here, so that the command line's ``--help`` imports no numpy.
"""

__all__: list[str] = []
