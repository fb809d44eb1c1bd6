"""Reading untrusted input: programs that expand a SOURCE (xacro) run in a confined child process.

:mod:`.child` starts and supervises such a process from urdf2dh; :mod:`.confine` is what the
process does to itself before it runs anything from the file; :mod:`.xacro_child` is the xacro
expansion that runs there. See ``docs/security.md``.
"""
