"""What urdf2dh writes: a table in text formats, as a URDF, as a picture or an interactive view,
and as controller and toolbox files.

* :mod:`.formats`: :func:`~.formats.render`, a table as text, JSON, YAML, CSV, Markdown, or as a
  model again (a URDF by :mod:`.urdf`, a POE model file);
* :mod:`.export`: controller and toolbox files, one module per target;
* :mod:`.plot`: a table's frames drawn (:mod:`.scene` decides what is shown, :mod:`.picture`
  draws it with matplotlib, :mod:`.view` with plotly, :mod:`.html` writes any plotly figure as a
  page that fetches nothing);
* :mod:`.names`: names made up for a file, kept clear of the robot's own (names from files
  are escaped for every language written by :mod:`urdf2dh.escape`).

Nothing is imported here, so that the command line's ``--help`` imports no numpy.
"""

__all__: list[str] = []
