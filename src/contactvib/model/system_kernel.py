"""The scaled form of a :class:`~contactvib.model.system.System` that the compiled integrator runs.

Scales: a time ``τ = ω t`` and per coordinate a length (or angle) ``L_j``, ``q_j = L_j x_j``; per
contact a force ``W_i`` and a deflection ``y0_i`` with ``F_s,i(y0_i) = W_i``, ``ξ_i = δ_i / y0_i``.
With ``A = diag(1/L) M⁻¹ / ω²`` the equation of :mod:`contactvib.model.system` becomes::

    x'' = g0 + gb cos(r τ) − Kx x − Cx x' − Σ_i [ξ_i > 0] Aw_i f_i(ξ_i, ξ_i'),
    ξ_i = U_i · x − γ_i,     ξ_i' = U_i · x'

``Kx = A K L``, ``Cx = ω A C L``, ``g0 = A f0``, ``gb = A b P_a``, ``r = 2π f_e / ω``,
``U_i = L w_i / y0_i``, ``γ_i = e_i / y0_i``, ``Aw_i = W_i A w_i``, and ``f_i = F_i / W_i`` the
compiled contact law of ``contactvib._kernels.contact`` (``contact_force``) on the parameter row
``rows[i]`` (the full ``par`` layout: spring code and data from the law's ``kernel_spring(y0_i,
W_i, S_i)``, damping code, ``c_i = S h_n y0_i^(l+1) ω / W_i`` (power) or ``α y0_i ω``
(Hunt–Crossley)).

The scales, chosen once per system (:func:`system_scales`):

* ``W_i`` the contact's static force where the static state engages it, else the reference
  force (the largest |f0|, or 1 N); ``y0_i`` the law's static deflection under ``W_i``;
* ``ω`` the largest natural angular frequency of the system linearised about the static state,
  open contacts counted with their stiffness at ``y0_i`` (1 rad/s if there is none), so the
  paper's slider runs in its own τ = ω_n0 t;
* ``L_j = min_i y0_i / |w_ij|`` over the contacts that move coordinate j (the slider: y0);
  a coordinate no contact moves takes the reference force over its stiffness,
  ``W_ref / max(K_ω,jj, M_jj ω²)`` (K_ω the stiffness that sets ω).

The integrator's tolerances are relative to these: atol = rtol in units of L_j and L_j ω.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

__all__ = ["SystemScales", "KernelForm", "system_scales", "kernel_form", "unit_form"]

@dataclass(frozen=True, eq=False)
class SystemScales:
    """Scales of the compiled form (module docstring).

    Attributes
    ----------
    length : ndarray (n,)
        L_j [m or rad] per coordinate.
    omega : float
        ω [rad/s]: τ = ω t.
    deflection : ndarray (m,)
        y0_i [m] per contact.
    force : ndarray (m,)
        W_i [N] per contact (F_s,i(y0_i) = W_i).
    """

    length: np.ndarray
    omega: float
    deflection: np.ndarray
    force: np.ndarray

    @property
    def state(self) -> np.ndarray:
        """D = (L, L ω): z_SI = D x for the state (q, q̇), shape (2n,)."""
        return np.concatenate([self.length, self.length * self.omega])

    def to_scaled(self, z) -> np.ndarray:
        """(q, q̇) [SI] → (x, x')."""
        return np.asarray(z, float) / self.state

    def to_si(self, x) -> np.ndarray:
        """(x, x') → (q, q̇) [SI] (along the first axis)."""
        x = np.asarray(x, float)
        d = self.state
        return x * d.reshape((-1,) + (1,) * (x.ndim - 1))

    def monodromy_to_si(self, phi) -> np.ndarray:
        """∂z_SI/∂z0_SI = D Φ D⁻¹ of a scaled monodromy Φ (2n × 2n)."""
        d = self.state
        return np.asarray(phi) * d[:, None] / d[None, :]


@dataclass(frozen=True, eq=False)
class KernelForm:
    """The arrays of the scaled equation (module docstring) at one excitation, for
    ``contactvib._kernels.system_flow.system_arrays``; ``scales`` converts to SI."""

    Kx: np.ndarray
    Cx: np.ndarray
    g0: np.ndarray
    gb: np.ndarray
    r: float
    U: np.ndarray
    gam: np.ndarray
    Aw: np.ndarray
    rows: np.ndarray
    scales: SystemScales

    @property
    def tau_period(self) -> float:
        """The excitation period in τ: 2π / r."""
        return 2.0 * math.pi / self.r


def _element_scales(system) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(W_i, y0_i, k_i) of each contact: its force scale [N], deflection [m] and the stiffness
    [N/m] that counts for ω (at the static state if engaged, else at y0_i)."""
    qs = system.static_state()
    W, y0, k = [], [], []
    for c in system.contacts:
        d = c.deflection(qs)
        Fs = c.spring_force(d) if d > 0.0 else 0.0
        Wi = Fs if Fs > 0.0 else system.reference_force
        yi = c.law.static_deflection(Wi, c.S)
        W.append(Wi)
        y0.append(yi)
        k.append(c.stiffness(d) if Fs > 0.0 else c.stiffness(yi))
    return np.array(W, float), np.array(y0, float), np.array(k, float)


def system_scales(system) -> SystemScales:
    """The scales of ``system`` (module docstring)."""
    from scipy.linalg import eigvals

    W, y0, k = _element_scales(system)
    n = system.n
    Kw = np.array(system.K)
    for c, ki in zip(system.contacts, k):
        Kw += ki * np.outer(c.w, c.w)
    lam = np.real(eigvals(Kw, system.M))
    w2 = float(np.max(lam)) if lam.size else 0.0
    omega = math.sqrt(w2) if w2 > 0.0 and math.isfinite(w2) else 1.0
    L = np.full(n, np.inf)
    for c, yi in zip(system.contacts, y0):
        w = np.abs(c.w)
        moved = w > 0.0
        L[moved] = np.minimum(L[moved], yi / w[moved])
    for j in range(n):  # no contact moves it: the static deflection under the reference force
        if not np.isfinite(L[j]):
            L[j] = system.reference_force / max(Kw[j, j], system.M[j, j] * omega * omega)
    return SystemScales(length=L, omega=omega, deflection=y0, force=W)


def _row(contact, y0: float, W: float, omega: float, kc) -> np.ndarray:
    """The kernel parameter row (``_kernels/contact.py``'s full ``par`` layout) of one contact."""
    code, s1, s2, data = contact.law.kernel_spring(y0, W, contact.S)
    if contact.damping == "hunt-crossley":
        dcode, l, c = kc.DAMPING_HUNT_CROSSLEY, 0.0, contact.alpha * y0 * omega
    else:
        dcode, l = kc.DAMPING_POWER, contact.l
        c = contact.S * contact.h_n * y0 ** (l + 1.0) * omega / W
    data = np.asarray(data, float)
    # par[0] is the power spring's exponent in the paper family's path (contact.force); unused otherwise
    head = np.array([s1 if code == kc.SPRING_POWER else 1.0, l, c, 0.0, 0.0, code, dcode, kc.EXCITATION_FORCE,
                     s1, kc.HEADER if data.size else s2, 0.0, kc.HEADER + data.size], dtype=float)
    return np.concatenate([head, data])


def unit_form(system) -> KernelForm:
    """The scaled arrays of ``system`` under P_a = 1 N at r = 1: what :func:`kernel_form` scales."""
    from contactvib._kernels import contact as kc

    sc = system.scales
    L, om = sc.length, sc.omega
    A = np.linalg.solve(system.M, np.eye(system.n)) / (om * om) / L[:, None]
    m = len(system.contacts)
    rows = [_row(c, sc.deflection[i], sc.force[i], om, kc) for i, c in enumerate(system.contacts)]
    width = max([kc.HEADER] + [r.size for r in rows])
    R = np.zeros((m, width))
    for i, r in enumerate(rows):
        R[i, :r.size] = r
    W_dir = system.directions
    return KernelForm(
        Kx=A @ system.K * L[None, :], Cx=om * (A @ system.C) * L[None, :], g0=A @ system.f0, gb=A @ system.b,
        r=1.0, U=W_dir * L[None, :] / sc.deflection[:, None] if m else np.zeros((0, system.n)),
        gam=np.array([c.engagement for c in system.contacts], float) / sc.deflection if m else np.zeros(0),
        Aw=(W_dir @ A.T) * sc.force[:, None] if m else np.zeros((0, system.n)),
        rows=R, scales=sc)


def kernel_form(system, pa_newton: float, fe_hz: float, unit: KernelForm | None = None) -> KernelForm:
    """The scaled arrays of ``system`` under P(t) = ``pa_newton`` cos(2π ``fe_hz`` t) [N]
    (from ``unit``, its :func:`unit_form`, when given)."""
    u = unit_form(system) if unit is None else unit
    return replace(u, gb=u.gb * float(pa_newton), r=2.0 * math.pi * float(fe_hz) / u.scales.omega)
