"""The ``urdf2dh`` command: a thin layer over the public API of :mod:`urdf2dh`. It parses the
options, calls the library, prints and writes; every job is a public function first.

* :mod:`.run`: :func:`main` and :func:`console`, one run of the command and the one place errors
  become exit codes and one-line messages;
* :mod:`.parser`: the argument parser, each command registered with its options
  (:class:`~.parser.Command`);
* :mod:`.options`: the options several commands share; :mod:`.chains`: several chains of one
  tree in one run;
* one module per command: :mod:`.convert`, :mod:`.verify`, :mod:`.diff`, :mod:`.info`,
  :mod:`.export`, :mod:`.plot`, :mod:`.robots`, :mod:`.measure`, :mod:`.calibrate`,
  :mod:`.plan`.

Nothing heavy is imported until a command runs: ``urdf2dh --help`` imports neither numpy,
yourdfpy nor Pinocchio.
"""

from __future__ import annotations

from .parser import get_argument_parser
from .run import console, main

__all__ = ["console", "get_argument_parser", "main"]
