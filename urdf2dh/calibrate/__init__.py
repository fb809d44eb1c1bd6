"""Kinematic calibration (issue 15): measured poses or points -> identified POE model -> every
table and controller file urdf2dh writes.

Modules: :mod:`.measurements` (CSV files), :mod:`.measure` (synthetic measurements),
:mod:`.chart` (the minimal local parametrisation, Wu 2019 eq. 23), :mod:`.residuals` (residuals
and their analytic Jacobian), :mod:`.solver` (Levenberg-Marquardt, statistics), :mod:`.frames`
(rigid fits), :mod:`.start` (options and the start), :mod:`.identify` (the identification),
:mod:`.report` and :mod:`.run` (one whole calibration), :mod:`.cli` (the ``measure`` and
``calibrate`` commands), :mod:`.lie` (batched SO(3)/SE(3) helpers).

Nothing is imported here, so that ``urdf2dh --help`` (which builds the commands' parsers from
:mod:`.cli`) does not import numpy.
"""
