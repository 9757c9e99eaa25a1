"""Branch switching at a period doubling of a system branch onto the period-2k branch.

Near a period-doubling point (x*, q*) of a period-k branch, with ``e`` the eigenvector of Φ for the
multiplier −1, the period-2k orbits are ``x* + ε e + O(ε²)`` at ``q* + O(ε²)`` (a pitchfork of
P^2k − x): the first point is corrected on the hyperplane through (x*, q*) normal to (e, 0) at a
scaled distance ``ds`` (halved until Newton's method lands on an orbit that is not of period k),
then the new branch is followed in one direction by :mod:`.system_shooting` until it merges with
the period-k branch again (``SystemOrbitProblem.sub_period``) or another stop.

References
----------
R. Seydel, *Practical Bifurcation and Stability Analysis*, 3rd ed., Springer (2010), Ch. 7.
"""

from __future__ import annotations

import numpy as np

from contactvib._kernels.status import STATUS_OK
from contactvib.continuation.engine import correct
from contactvib.continuation.system_branch import SystemBranch, SystemSpecialPoint
from contactvib.continuation.system_shooting import SystemContinuationSettings, SystemOrbitProblem
from contactvib.errors import ComputationError
from contactvib.model import ParameterError
from contactvib.model.system import System

__all__ = ["switch_system_period_doubling"]


def switch_system_period_doubling(system: System, special: SystemSpecialPoint, *, parameter: str = "f_e",
                                  settings: SystemContinuationSettings | None = None, branch_id: str | None = None,
                                  Q: float | None = None, coordinate: int = 0, ds: float = 0.01) -> SystemBranch:
    """The period-2k branch born at the ``"period-doubling"`` point ``special`` of a system branch
    (:func:`.system_shooting.continue_system_orbit`), continued in ``parameter`` ("f_e" or "P_a").

    Raises
    ------
    ParameterError
        ``special`` is not a period-doubling point.
    ComputationError
        No period-2k orbit found next to the point (``stage`` "continuation").
    """
    if not isinstance(special, SystemSpecialPoint) or special.type != "period-doubling":
        raise ParameterError("special", getattr(special, "type", special), "must be a period-doubling point "
                                                                            "of a system branch")
    settings = settings or SystemContinuationSettings()
    k = int(special.period)
    pa, fe = float(special.pa_newton), float(special.fe_hz)
    bid = branch_id or f"{special.branch}.pd{k}"
    prob_k = SystemOrbitProblem(system, pa, fe, k, parameter, settings, Q, coordinate)
    q_star = fe if parameter == "f_e" else pa
    st, pk = prob_k.fix_q(np.append(prob_k.scales.to_scaled(special.state), q_star))
    if st != STATUS_OK:
        raise ComputationError("the period-doubling point could not be re-converged", stage="continuation")
    vals, vecs = np.linalg.eig(pk.data)
    e = np.real(vecs[:, int(np.argmin(np.abs(vals + 1.0)))])
    prob = SystemOrbitProblem(system, pa, fe, 2 * k, parameter, settings, Q, coordinate)
    u_star = pk.u
    t_dir = np.append(e, 0.0)
    w = prob.weights(u_star)
    tau = t_dir * w / np.linalg.norm(t_dir * w)
    for _ in range(10):
        st, pt = correct(prob, u_star + ds * tau / w, u_star, tau, w, ds, prob.corrector)
        if st == STATUS_OK and prob.sub_period(pt.u) is None:
            break
        ds *= 0.5
    else:
        raise ComputationError(f"no period-{2 * k} branch found at the period doubling f_e = {fe:.6g} Hz, "
                               f"P_a = {pa:.6g} N", stage="continuation")
    points, specials, stop = prob.run(pt, t_dir, bid)
    return prob.branch(points, specials, [stop], bid, settings=settings.to_dict())
