"""The geometry everything else is built on: rigid transforms, screws and lines.

* :mod:`.frames`: rigid frames as plain floats (no numpy), for the chain walks and conversions
  that compose one frame at a time; angles in ``(-pi, pi]``, unit vectors.
* :mod:`.se3`: the small Lie-group kit in numpy: ``(4, 4)`` transforms, ``exp`` of twists
  ``[w, v]``, the adjoint, roll-pitch-yaw, pose errors.
* :mod:`.lie`: the same group, batched: stacks of rotations and transforms, ``exp`` and ``log``
  and their Jacobians, quaternions.
* :mod:`.normals`: the common normal of two lines, the core of every D-H conversion (Wu,
  Crawford & Roberts 2019, Lemmas 1-4).

Nothing is imported here, so that the command line's ``--help`` needs no numpy.
"""

__all__: list[str] = []
