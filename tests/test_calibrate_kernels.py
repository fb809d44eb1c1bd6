"""The residual kernels' scratch space (:func:`urdf2dh.calibration.residuals._scratch`): reused
from call to call, grown when a larger problem comes, one per thread, and never seen in a result.
"""

from __future__ import annotations

import threading

import numpy as np
from test_calibrate_math import CASES, _case

from urdf2dh.calibration import residuals as residuals_module
from urdf2dh.calibration.residuals import Evaluation, evaluate


def _problems() -> list[tuple]:
    """Every case of the math tests, each with all its measurements and with its first five."""
    out = []
    for case in CASES:
        est, data, sp, sr = _case(case)
        out += [(est, data, sp, sr), (est, data.part(slice(0, 5)), sp, sr)]
    return out


def test_jacobians_in_any_order_and_any_thread_are_those_made_alone():
    """Each problem's residuals and Jacobian, made first, again after larger and smaller ones
    (the scratch space grown and reused), and in four threads at once, are the same bit for bit;
    no result shares memory with a scratch space."""
    problems = _problems()
    alone = [evaluate(*p) for p in problems]
    again = [evaluate(*p) for p in reversed(problems)][::-1]
    made: dict[int, dict[int, tuple]] = {}

    def run(k: int) -> None:  # each thread from another problem on
        order = [*range(k, len(problems)), *range(k)]
        made[k] = {i: evaluate(*problems[i]) for i in order}

    threads = [threading.Thread(target=run, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    spaces = residuals_module._SPACE.spaces
    for k, (r, jac) in enumerate(alone):
        for other in (again[k], *(made[t][k] for t in range(4))):
            assert np.array_equal(other[0], r) and np.array_equal(other[1], jac)
        assert not any(np.shares_memory(jac, s) for s in spaces)
    est, data, _, _ = problems[0]
    model = Evaluation.at(est, data)
    evaluate(*problems[2])  # another Jacobian between the residuals and this one's
    assert np.array_equal(model.jacobian(), evaluate(est, data, 1.0, 1.0)[1])
