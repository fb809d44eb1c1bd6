"""What urdf2dh writes for people to look at: a table's frames as a picture (png, svg, pdf) or
as an interactive 3-D view (one self-contained HTML page).

:mod:`.scene` decides what is shown (frames, axes, labels, hover text, the view) from a
:class:`~urdf2dh.conventions.table.Table`; :mod:`.picture` draws it with matplotlib, :mod:`.view`
with plotly, and :mod:`.html` writes any plotly figure as an offline page. :func:`.plot.plot` picks
the drawing by format.
"""
