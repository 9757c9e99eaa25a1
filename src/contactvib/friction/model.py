"""The tangential model: friction under normal contact vibration, its parameters.

A second coordinate u along the slideway. The slider (mass M) is pulled by a drive spring k_d
and damper c_d whose end moves at v_d::

    M ü = k_d (v_d t − u) + c_d (v_d − u̇) − F_t

F_t is the contact's tangential force, a Jenkins element (elastic pre-sliding): a tangential
contact stiffness k_t in series with a Coulomb slip element of limit μ R⁺(t) (or Hess & Soom's
real-area law μ W (R⁺/W)^β), R(t) the normal contact force of a normal attractor (Kostek 2013's
model, R = 0 in flight) and W = Q + F_pre. Stick: dF_t = k_t (du − 0) (Mindlin's incremental
form); slip: F_t = ±limit; no compression (flight, or the damper pulling just before a
separation): F_t = 0 and the spring relaxes. k_t follows the normal contact,
k_t = kt_ratio · dF_s/dy (y(t)) (``kt_law="normal"``; for Hertz asperities Mindlin's ratio
k_t/k_n = 2(1 − ν)/(2 − ν) = 0.8235 at ν = 0.3, the default), or is constant,
kt_ratio · dF_s/dy (y0) (``kt_law="constant"``).

Limits of the model: planar (no rocking of the slider), and one-way: the normal motion does not
feel the tangential one (no normal–tangential coupling through the contact).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from contactvib.model.checks import ParameterError, check_choice, check_range

#: Mindlin's ratio of tangential to normal stiffness of a Hertz contact, 2(1 − ν)/(2 − ν) at ν = 0.3.
MINDLIN_RATIO = 2.0 * (1.0 - 0.3) / (2.0 - 0.3)
KT_LAWS = ("normal", "constant")
#: Drives of the slider: the end of a drive spring moving at v_d (v_d = 0: the spring at rest,
#: holding the slider; see :class:`FrictionModel`), or a constant tangential force
#: F_T (with the damper c_d to the ground).
DRIVES = ("velocity", "force")


@dataclass(frozen=True)
class FrictionModel:
    """Parameters of the tangential motion (units in the names' documentation).

    Parameters
    ----------
    mu : float
        Coulomb friction coefficient μ [1], > 0 (default 0.3).
    kt_ratio : float
        Tangential contact stiffness over the normal contact stiffness dF_s/dy [1], > 0
        (default Mindlin's 0.8235).
    kt_law : {"normal", "constant"}
        k_t follows the normal stiffness along the orbit (dF_s/dy at y(t)) or is held at its
        static value (dF_s/dy at y0).
    kd : float
        Drive spring stiffness k_d [N/m], > 0 (default 1e5).
    cd : float
        Drive damper c_d [N s/m], ≥ 0 (default 30: a damping ratio of about 0.1 of the slider on
        the drive spring).
    vd : float
        Drive velocity v_d [mm/s], ≥ 0 (default 0.1). v_d = 0: the drive spring at rest holds
        the slider. It starts stretched to the static friction limit μ W (the drive stopped at
        the onset of sliding) and the vibration lets the slider creep until the spring's force
        is what the vibrating contact holds; ``friction_ratio`` is then that held mean
        tangential force ⟨F_drive⟩ / (μ W) (1: the contact holds the full static load; < 1:
        the vibration relaxed part of it; 0 where the contact flies and the spring relaxes
        completely). No drive work: the energy residual is NaN.
    beta : float
        Hess & Soom's exponent β of the slip limit μ W (R/W)^β [1], 0 < β ≤ 1 (1: Coulomb, μ R).
    drive : {"velocity", "force"}
        The drive: the end of the drive spring moves at v_d; or a constant tangential force
        ``ft`` pulls the slider (k_d and v_d unused, c_d a damper to the ground): the slider then
        creeps at the mean velocity the vibration lets through.
    ft : float
        The constant tangential force F_T [N] of ``drive="force"``, > 0 there (0 otherwise).
    """

    mu: float = 0.3
    kt_ratio: float = MINDLIN_RATIO
    kt_law: str = "normal"
    kd: float = 1e5
    cd: float = 30.0
    vd: float = 0.1
    beta: float = 1.0
    drive: str = "velocity"
    ft: float = 0.0

    def __post_init__(self):
        put = object.__setattr__
        put(self, "mu", check_range("mu", self.mu, 0.0, False, "1", upper=100.0))
        put(self, "kt_ratio", check_range("kt_ratio", self.kt_ratio, 0.0, False, "1", upper=1e6))
        put(self, "kt_law", check_choice("kt_law", self.kt_law, KT_LAWS))
        put(self, "drive", check_choice("drive", self.drive, DRIVES))
        kd = check_range("k_d", self.kd, None, unit="N/m", upper=1e15)
        if kd <= 0.0:
            raise ParameterError("k_d", self.kd, "must be > 0 N/m: the drive velocity v_d acts through a drive "
                                 "spring (or drive='force' with a constant tangential force ft)")
        put(self, "kd", kd)
        put(self, "cd", check_range("c_d", self.cd, 0.0, True, "N s/m", upper=1e12))
        put(self, "vd", check_range("v_d", self.vd, 0.0, True, "mm/s", upper=1e6))
        put(self, "beta", check_range("beta", self.beta, 0.0, False, "1", upper=1.0))
        if self.drive == "force":
            put(self, "ft", check_range("F_T", self.ft, 0.0, False, "N", upper=1e12))
        elif check_range("F_T", self.ft, None, unit="N") != 0.0:
            raise ParameterError("F_T", self.ft, "belongs to drive='force' (a constant tangential force), "
                                 "not to the velocity drive")

    def parameters(self) -> dict:
        """The parameters as a dict (JSON, dataset attributes)."""
        if "_parameters" not in self.__dict__:  # computed once: a sweep asks at every point
            object.__setattr__(self, "_parameters", asdict(self))
        return dict(self.__dict__["_parameters"])

    def kernel_parameters(self, model) -> np.ndarray:
        """``tpar`` of ``contactvib._kernels.friction`` for ``model``: μ, β, kt_ratio, the
        constant-k_t flag, k_d y0/W, c_d y0 ω_n0/W, v_d/(y0 ω_n0), κ, F_T/W (k_d = v_d = 0 under a
        force drive, F_T = 0 under the velocity drive)."""
        y0, w, W = model.y0, model.omega_n0, model.W
        force = self.drive == "force"
        return np.array([self.mu, self.beta, self.kt_ratio, 1.0 if self.kt_law == "constant" else 0.0,
                         0.0 if force else self.kd * y0 / W, self.cd * y0 * w / W,
                         0.0 if force else self.vd * 1e-3 / (y0 * w), model.kappa, self.ft / W])

    def scales(self, model, tpar=None) -> np.ndarray:
        """Scales of w [y0], w' and f_t [W] for error control and the steady-state test: the
        elastic displacement μ/k_t (inf under a force drive: u drifts, its error does not act
        back and it is not compared), the drive velocity plus the stick oscillation's velocity,
        and μ (``tpar``: :meth:`kernel_parameters` of ``model`` if known)."""
        tp = self.kernel_parameters(model) if tpar is None else tpar
        kt0 = self.kt_ratio * model.kappa
        w = math.inf if self.drive == "force" else self.mu / kt0  # a force drive's u drifts: not compared
        return np.array([w, tp[6] + self.mu / math.sqrt(kt0 * model.kappa), self.mu])
