"""Reading untrusted input: programs that expand a SOURCE (xacro) run in a confined child process;
YAML and JSON are read as YAML 1.2 and JSON read them, within bounds.

:mod:`.child` starts and supervises such a process from urdf2dh; :mod:`.confine` is what the
process does to itself before it runs anything from the file; :mod:`.xacro_child` is the xacro
expansion that runs there. See ``docs/security.md``. :mod:`.mappings` reads POE and table files
(``docs/limits.md``).
"""
