"""Alternating frequency–time (AFT) transforms of a truncated Fourier series (harmonic balance).

Real coefficient vector ``X = [a0, a1, b1, ..., aH, bH]`` of ``x(θ) = a0 + Σ (a_k cos kθ +
b_k sin kθ)``; samples on ``n_time`` equispaced points of θ ∈ [0, 2π); numpy FFT only.

References
----------
T. M. Cameron, J. H. Griffin, J. Appl. Mech. 56 (1989) 149–154.
"""

from __future__ import annotations

import numpy as np

__all__ = ["AFT"]


class AFT:
    """AFT on n_time samples of θ ∈ [0, 2π) for H harmonics, FFT only (no dense products).

    The Jacobian of the projected product ``P(g · basis_k)`` is assembled from the Fourier
    coefficients G_m of g (|m| ≤ 2H) by index arithmetic: cos kθ and sin kθ map onto
    G_{j−k} ± G_{j+k}. (Dense synthesis/projection matrices would need BLAS products with an
    n_time-long inner dimension, which collapse when the machine's cores are oversubscribed.)
    """

    def __init__(self, H: int, n_time: int):
        self.H = H
        self.n = n_time
        k = np.arange(1, H + 1)
        d2 = np.zeros(2 * H + 1)
        d2[1::2] = -(k ** 2)
        d2[2::2] = -(k ** 2)
        self.d2 = d2
        self.k = k
        j = np.arange(0, H + 1)[:, None]
        kk = np.arange(1, H + 1)[None, :]
        self.jm = j - kk   # indices j − k, in −H..H−1
        self.jp = j + kk   # indices j + k, in 2..2H
        self.j = np.arange(0, H + 1)

    def synth(self, X):
        """Samples of x and x_θ from [a0, a1, b1, ...]."""
        H, n = self.H, self.n
        C = np.zeros(n // 2 + 1, complex)
        C[0] = X[0]
        C[1:H + 1] = 0.5 * (X[1::2] - 1j * X[2::2])
        x = np.fft.irfft(C * n, n)
        xt = np.fft.irfft(1j * np.arange(n // 2 + 1) * C * n, n)
        return x, xt

    def project(self, f):
        """[a0, a1, b1, ...] of the samples f (harmonics ≤ H)."""
        F = np.fft.rfft(f) / self.n
        out = np.empty(2 * self.H + 1)
        out[0] = F[0].real
        out[1::2] = 2.0 * F[1:self.H + 1].real
        out[2::2] = -2.0 * F[1:self.H + 1].imag
        return out

    def product_matrix(self, g):
        """Matrix of X ↦ P(g · x) on the real coefficient vector."""
        H = self.H
        F = np.fft.rfft(g) / self.n

        def G(m):
            v = F[np.abs(m)]
            return np.where(m < 0, np.conj(v), v)

        Gm, Gp = G(self.jm), G(self.jp)  # shape (H+1, H)
        S, D = Gm + Gp, Gm - Gp
        T = np.empty((2 * H + 1, 2 * H + 1))
        G0 = F[: H + 1]
        T[0, 0] = G0[0].real
        T[1::2, 0] = 2.0 * G0[1:].real
        T[2::2, 0] = -2.0 * G0[1:].imag
        # columns of cos kθ
        T[0, 1::2] = S[0].real / 2.0
        T[1::2, 1::2] = S[1:].real
        T[2::2, 1::2] = -S[1:].imag
        # columns of sin kθ
        T[0, 2::2] = D[0].imag / 2.0
        T[1::2, 2::2] = D[1:].imag
        T[2::2, 2::2] = D[1:].real
        return T

    def times_derivative(self, T):
        """T @ D_θ, with D_θ the derivative on the coefficient vector (a_k' = k b_k, b_k' = −k a_k)."""
        out = np.zeros_like(T)
        out[:, 1::2] = -self.k * T[:, 2::2]
        out[:, 2::2] = self.k * T[:, 1::2]
        return out
