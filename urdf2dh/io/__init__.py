"""SOURCE -> model: reading what urdf2dh is given, and writing what it makes, safely.

* :mod:`.sources`: the one table of readers (:data:`~.sources.READERS`: the formats, how each is
  recognised, the module that reads it). :func:`~.sources.open_source` resolves a SOURCE (a
  file in one of those formats, or a bundled robot from :mod:`.catalog`) once;
  :meth:`~.sources.Source.model` builds the POE model of a chain of it.
* :mod:`.urdf`: URDF XML -> one strict check -> kinematic tree -> serial chain -> POE model.
* :mod:`.xacro`: ``.xacro`` expanded in a confined child process (:mod:`.child` runs it,
  :mod:`.confine` is what it does to itself, :mod:`.xacro_child` is the expansion;
  ``docs/security.md``).
* :mod:`.poefile` and :mod:`.tablefile`: POE model files and table files (YAML or JSON, read by
  :mod:`.mappings` as YAML 1.2 and JSON read them, their values checked by :mod:`.fields`);
  :mod:`.encodings`: what a file's bytes hold.
* :mod:`.files`: every file a run reads is one of its inputs, and no output replaces one;
  outputs are written all together or not at all. :mod:`.interrupts`: Ctrl-C and ``SIGTERM``
  end a run with nothing changed.

Nothing is imported here, so that the command line's ``--help`` imports no numpy.
"""

__all__: list[str] = []
