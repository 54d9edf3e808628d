"""Planar finite-element reference for slab-to-column pounding (issue 23), and the reduced
model pound would implement. Written for the tests from textbook formulas; it imports nothing
from pound. Units are SI throughout: m, s, kg, N, N·m, Pa.

Physics (one horizontal direction x, positive from the neighbour towards the struck building)
-------------------------------------------------------------------------------------------
* The struck building A: N storeys of heights h_i between rigid floors; floor i (i = 1..N) has
  one lateral DOF u_i (relative to the ground, floor 0) and lumped mass m_i. Floors do not
  rotate about the horizontal axis, so every column is clamped at both ends (the shear-type
  assumption). Storey i holds n_c identical columns (E, I, height h_i, optional distributed
  mass ρA kg/m).
* Columns are Euler–Bernoulli beams in cubic Hermite elements (DOFs w, θ = dw/dz at each node;
  stiffness EI/L³·[[12, 6L, −12, 6L], …], consistent mass ρAL/420·[[156, 22L, 54, −13L], …]).
  Storey i has one explicit *struck* column (the contact storey only) and the other columns
  either explicit too (`other_columns="beam"`: n identical columns with identical end motions
  respond identically, so one beam with n·EI and n·ρA is exact) or lumped
  (`other_columns="lumped"`: stiffness n·12EI/h³ between the floors and mass n·ρAh/2 added to
  each end floor), or `"guyan"`: that stiffness with the consistent mass of the storey shapes
  (ρAh·[[13/35, 9/70], [9/70, 13/35]]), the static condensation of a beam without its local
  dynamics. The struck column is always explicit, with a node exactly at the contact
  height z = z_(i−1) + ξ·h_i.
* With ρA = 0 every column DOF is massless and is condensed statically (Guyan) phase by phase,
  the contact node too: the contact spring then acts in series with the column's local
  flexibility a³b³/(3EIh³).
* The neighbour B: a shear building (floor masses, storey springs to its ground; one storey is
  a SDOF, a zero spring a free mass). Its contact floor (the roof by default) meets the struck
  column through a one-sided spring k_c (N/m), an optional dashpot c_c (N·s/m) in parallel
  that acts only while the contact pushes, and an initial gap g ≥ 0. Penetration
  δ = x_slab − x_node − g; force F = k_c·δ + c_c·δ̇ while in contact (F ≥ 0), acting +x on the
  column and −x on the slab. A contact starts when δ reaches 0 from below (or, after a release
  with δ > 0 because of the dashpot, when k_c·δ + c_c·δ̇ rises through 0) and ends when F
  falls to 0.
* Loading: initial velocities (an impact test) and optionally a ground acceleration a_g(t),
  piecewise linear between samples, applied as the explicit load −M·r·a_g, where r is the
  rigid translation of *all* lateral DOFs including the ground nodes (so consistent-mass
  couplings to the ground are counted once, and nothing is double counted).
* Integration: the system is linear between contact events (and between ground-motion
  samples). Each such phase is solved in closed form: real modal superposition when it is
  undamped (generalised symmetric eigenproblem, rigid-body modes as polynomials), otherwise
  the complex eigenvectors of the first-order system (massless DOFs with a dashpot become
  first-order states). Contact start and end are located by conservative advancement on the
  closed-form event function (a step can never pass a root because |f''| is bounded by
  Σ|c_i||λ_i|²), which converges quadratically to the root; events are found to ~1e-14 s.
  Undamped runs conserve energy to rounding.

Everything a test or the study reads is in `Result`: contact phases (every impact), the
contact force and the struck column's end shears/moments sampled on a uniform grid with exact
running integrals (for impulses and window averages), exact peaks, and storey drifts.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
import scipy.linalg
import scipy.optimize

# ---------------------------------------------------------------------------------------------
# Closed forms
# ---------------------------------------------------------------------------------------------


def storey_shape(xi):
    """s(ξ) = 3ξ² − 2ξ³: the deflected shape of a column clamped at both ends whose top moves
    by 1 relative to its bottom (the shear-type storey outline)."""
    xi = np.asarray(xi, dtype=float)
    return 3.0 * xi**2 - 2.0 * xi**3


def point_load_flexibility(EI, h, xi):
    """Deflection under a unit point load at a = ξh of a column of height h (m) clamped at both
    (non-moving) ends: a³b³/(3·EI·h³) (m/N), b = h − a."""
    a = xi * h
    b = h - a
    return a**3 * b**3 / (3.0 * EI * h**3)


def fixed_fixed_point_load(P, a, h, EI):
    """Textbook results for a clamped–clamped beam of span h with a point load P (N) at a (m)
    from the bottom end: deflection under the load (m), end shears (N) and end moments (N·m),
    all as magnitudes of the support reactions (b = h − a)."""
    b = h - a
    return {
        "deflection": P * a**3 * b**3 / (3.0 * EI * h**3),
        "V_bottom": P * b**2 * (3 * a + b) / h**3,
        "V_top": P * a**2 * (a + 3 * b) / h**3,
        "M_bottom": P * a * b**2 / h**2,
        "M_top": P * a**2 * b / h**2,
    }


def hermite_shapes(x, L):
    """Cubic Hermite shape functions of a beam element of length L at x ∈ [0, L], for the DOFs
    (w₁, θ₁, w₂, θ₂): N₁ = 1 − 3ζ² + 2ζ³, N₂ = x(1 − ζ)², N₃ = 3ζ² − 2ζ³, N₄ = x(ζ² − ζ),
    ζ = x/L. A point load P at x has the consistent nodal forces P·N(x) (virtual work)."""
    z = x / L
    return np.array([1 - 3 * z**2 + 2 * z**3, x * (1 - z) ** 2, 3 * z**2 - 2 * z**3, x * (z**2 - z)])


def beam_stiffness(EI, L):
    """Euler–Bernoulli element stiffness (N/m, N, N·m) for (w₁, θ₁, w₂, θ₂)."""
    return EI / L**3 * np.array(
        [[12, 6 * L, -12, 6 * L], [6 * L, 4 * L**2, -6 * L, 2 * L**2],
         [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L**2, -6 * L, 4 * L**2]])  # fmt: skip


def beam_mass(rhoA, L):
    """Consistent mass matrix (kg, kg·m, kg·m²) of the Hermite element, ρA in kg/m."""
    return rhoA * L / 420.0 * np.array(
        [[156, 22 * L, 54, -13 * L], [22 * L, 4 * L**2, 13 * L, -3 * L**2],
         [54, 13 * L, 156, -22 * L], [-13 * L, -3 * L**2, -22 * L, 4 * L**2]])  # fmt: skip


# --- clamped–clamped beam modes -----------------------------------------------------------------


@lru_cache(maxsize=None)
def clamped_beta(k):
    """β_k·L of the k-th (1-based) mode of a clamped–clamped beam: cos(βL)·cosh(βL) = 1
    (4.730041, 7.853205, 10.995608, …)."""
    f = lambda x: np.cos(x) - 1.0 / np.cosh(x)  # noqa: E731  (same roots, no overflow)
    x0 = (k + 0.5) * np.pi
    return float(scipy.optimize.brentq(f, x0 - 0.5, x0 + 0.5, xtol=1e-15, rtol=1e-15))


def clamped_mode(k, xi, derivative=0):
    """Mode k of a clamped–clamped beam as a function of ξ = z/L, normalised so that
    ∫₀¹ φ² dξ = 1 (the classical form cosh − cos − σ(sinh − sin) has this property), and its
    first or second derivative with respect to ξ. Evaluated without the cancellation of cosh and
    sinh: cosh x − σ sinh x = ½(1 − σ)eˣ + ½(1 + σ)e⁻ˣ with 1 − σ computed directly."""
    B = clamped_beta(k)
    x = B * np.asarray(xi, dtype=float)
    den = np.sinh(B) - np.sin(B)
    sigma = (np.cosh(B) - np.cos(B)) / den
    one_minus = (np.cos(B) - np.sin(B) - np.exp(-B)) / den  # 1 − σ
    ep = 0.5 * one_minus * np.exp(x)
    em = 0.5 * (1.0 + sigma) * np.exp(-x)
    if derivative == 0:
        return ep + em - np.cos(x) + sigma * np.sin(x)
    if derivative == 1:
        return B * (ep - em + np.sin(x) + sigma * np.cos(x))
    if derivative == 2:
        return B**2 * (ep + em + np.cos(x) - sigma * np.sin(x))
    raise ValueError(derivative)


@lru_cache(maxsize=None)
def _gauss(n=400):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def clamped_modal_data(k, xi):
    """Per-length-normalised modal constants of clamped mode k for a contact at ξ, all as
    integrals over ξ ∈ [0, 1] (multiply by ρA·h, ρA·h², EI/h³ for dimensions):
    phi_xi = φ_k(ξ); bb = (∫(1 − s)φ, ∫sφ) (translational couplings to the end floors);
    th = (∫ξ(1 − ξ)²φ, ∫ξ²(ξ − 1)φ) (couplings to the end rotations, for the end moments);
    beta4 = (β_k L)⁴ (modal stiffness EI·β⁴/h³ for unit modal mass ρA·h)."""
    z, w = _gauss()
    phi = clamped_mode(k, z)
    s = storey_shape(z)
    return {
        "phi_xi": float(clamped_mode(k, xi)),
        "bb": np.array([w @ ((1 - s) * phi), w @ (s * phi)]),
        "th": np.array([w @ (z * (1 - z) ** 2 * phi), w @ (z**2 * (z - 1) * phi)]),
        "beta4": clamped_beta(k) ** 4,
    }


# ---------------------------------------------------------------------------------------------
# Closed-form phase solutions
# ---------------------------------------------------------------------------------------------


class Signal:
    """f(τ) = Re Σᵢ cᵢ·exp(λᵢτ) + Σₖ pₖ·τᵏ, τ measured from the start of a phase (s)."""

    __slots__ = ("lam", "c", "p")

    def __init__(self, lam, c, p):
        self.lam = lam
        self.c = c
        self.p = np.asarray(p, dtype=float)

    def __call__(self, tau):
        if np.ndim(tau) == 0:  # scalar fast path (event and peak searches)
            t = float(tau)
            v = 0.0
            for pk in self.p[::-1]:
                v = v * t + pk
            return float((np.exp(self.lam * t) @ self.c).real) + v
        tau = np.asarray(tau, dtype=float)
        e = np.exp(np.multiply.outer(tau, self.lam))
        return (e @ self.c).real + np.polynomial.polynomial.polyval(tau, self.p)

    def deriv(self):
        return Signal(self.lam, self.c * self.lam, np.polynomial.polynomial.polyder(self.p) if self.p.size > 1 else [0.0])

    def integral(self):
        """Antiderivative that vanishes at τ = 0 (no λ is zero: rigid-body terms are polynomials)."""
        ci = self.c / self.lam
        p = np.polynomial.polynomial.polyint(self.p)
        p[0] -= ci.sum().real
        return Signal(self.lam, ci, p)

    def __add__(self, other):
        if self.lam is not other.lam:
            raise ValueError("signals of different phases")
        n = max(self.p.size, other.p.size)
        return Signal(self.lam, self.c + other.c, np.pad(self.p, (0, n - self.p.size)) + np.pad(other.p, (0, n - other.p.size)))


class Trajectory:
    """x(τ) = Re(exp(λτ)·Z) + P(τ) for all DOFs of the model over one phase."""

    def __init__(self, lam, Z, P):
        self.lam, self.Z, self.P = lam, Z, P  # (m,), (m, n), (deg+1, n)

    def _poly(self, tau, d):
        P = self.P
        for _ in range(d):
            P = P[1:] * np.arange(1, P.shape[0])[:, None] if P.shape[0] > 1 else np.zeros((1, P.shape[1]))
        return np.polynomial.polynomial.polyval(np.asarray(tau, dtype=float), P).T

    def x(self, tau, d=0):
        e = np.exp(np.multiply.outer(np.asarray(tau, dtype=float), self.lam)) * self.lam**d
        return (e @ self.Z).real + self._poly(tau, d)

    def signal(self, Dx=None, Dv=None, Da=None, const=0.0, ga=0.0, ag=(0.0, 0.0)):
        """Signal of Dx·x + Dv·ẋ + Da·ẍ + ga·a_g(τ) + const with a_g(τ) = ag[0] + ag[1]·τ."""
        lam = self.lam
        c = np.zeros(lam.size, complex)
        p = np.zeros(self.P.shape[0] + 1)
        p[0] += const + ga * ag[0]
        p[1] += ga * ag[1]
        for D, d in ((Dx, 0), (Dv, 1), (Da, 2)):
            if D is None:
                continue
            c += (self.Z @ D) * lam**d
            q = self.P @ D
            for _ in range(d):
                q = q[1:] * np.arange(1, q.size) if q.size > 1 else np.zeros(1)
            p[: q.size] += q
        return Signal(lam, c, p)


RIGID_OMEGA2 = 1e-6  # rad²/s²: modes below this (periods above ~6000 s) are rigid-body modes


class LinearPhase:
    """M·ẍ + C·ẋ + K·x = f₀ + f₁·τ for one contact configuration, solved in closed form.

    DOFs with zero mass are either first-order (a positive dashpot on the diagonal: a massless
    node behind a contact dashpot) or static and condensed (Guyan): x_s = K_ss⁻¹(f_s − K_sr·x_r).
    M must not couple massless DOFs, and C must not touch static ones."""

    def __init__(self, M, C, K):
        n = M.shape[0]
        massive = np.diag(M) > 0
        damped = (~massive) & (np.diag(C) > 0)
        static = (~massive) & (~damped)
        if np.any(M[np.ix_(~massive, np.arange(n))]):
            raise ValueError("mass couples a massless DOF")
        if np.any(C[np.ix_(static, np.arange(n))]):
            raise ValueError("damping touches a static (massless, undamped) DOF")
        self.n = n
        self.a = np.flatnonzero(massive)
        self.d = np.flatnonzero(damped)
        self.s = np.flatnonzero(static)
        self.r = np.concatenate([self.a, self.d])
        r, s = self.r, self.s
        # static condensation: x = T·x_r + S·f
        self.T = np.zeros((n, r.size))
        self.T[r, np.arange(r.size)] = 1.0
        self.S = np.zeros((n, n))
        if s.size:
            Kss = K[np.ix_(s, s)]
            Ksr = K[np.ix_(s, r)]
            self.T[s] = -np.linalg.solve(Kss, Ksr)
            self.S[np.ix_(s, s)] = np.linalg.inv(Kss)
        # reduced operators: K* = Tᵀ K T, loads f* = Tᵀ f (f on static DOFs is carried by T)
        self.Ks = self.T.T @ K @ self.T
        Cr = C[np.ix_(r, r)]
        na, nd = self.a.size, self.d.size
        Ma = M[np.ix_(self.a, self.a)]
        self.real = nd == 0 and not np.any(Cr)
        if self.real:
            # Jacobi scaling (unit mass diagonal) keeps rotational DOFs with tiny inertia from
            # spoiling the conditioning of the modal basis
            Dm = 1.0 / np.sqrt(np.diag(Ma))
            w2, Phi = scipy.linalg.eigh(Dm[:, None] * self.Ks * Dm, Dm[:, None] * Ma * Dm)
            Phi = Dm[:, None] * Phi
            self.w2 = np.where(w2 < RIGID_OMEGA2, 0.0, w2)
            self.Phi = Phi
            self.PhiTM = Phi.T @ Ma
        else:
            Kaa, Kad = self.Ks[:na, :na], self.Ks[:na, na:]
            Kda, Kdd = self.Ks[na:, :na], self.Ks[na:, na:]
            Caa, Cad = Cr[:na, :na], Cr[:na, na:]
            Cda, Cdd = Cr[na:, :na], Cr[na:, na:]
            Mi = np.linalg.inv(Ma)
            Cddi = np.linalg.inv(Cdd) if nd else np.zeros((0, 0))
            # ẋ_d = Cdd⁻¹(f_d − Cda v − Kda x − Kdd w); v̇ = Ma⁻¹(f_a − Caa v − Kaa x − Kad w − Cad ẋ_d)
            N = 2 * na + nd
            A = np.zeros((N, N))
            B = np.zeros((N, na + nd))
            ia, iv, iw = slice(0, na), slice(na, 2 * na), slice(2 * na, N)
            A[ia, iv] = np.eye(na)
            Wx = -Cddi @ Kda
            Wv = -Cddi @ Cda
            Ww = -Cddi @ Kdd
            Wf = np.hstack([np.zeros((nd, na)), Cddi])
            A[iw, ia], A[iw, iv], A[iw, iw] = Wx, Wv, Ww
            B[iw] = Wf
            A[iv, ia] = -Mi @ (Kaa + Cad @ Wx)
            A[iv, iv] = -Mi @ (Caa + Cad @ Wv)
            A[iv, iw] = -Mi @ (Kad + Cad @ Ww)
            B[iv] = Mi @ (np.hstack([np.eye(na), np.zeros((na, nd))]) - Cad @ Wf)
            lam, V = scipy.linalg.eig(A)
            if np.min(np.abs(lam)) < 1e-9 * max(1.0, np.max(np.abs(lam))) or np.linalg.cond(V) > 1e10:
                raise ValueError("a damped phase with a rigid-body (defective) mode: ground the bodies by springs")
            self.lam_c, self.V, self.Vi, self.B = lam, V, np.linalg.inv(V), B
            self.xrows = np.concatenate([np.arange(na), 2 * na + np.arange(nd)])  # displacements in y

    def trajectory(self, x0, v0, f0, f1):
        """Closed-form solution from the full-DOF state (x₀, v₀) (only massive displacements and
        velocities and first-order DOFs' displacements are used) under f₀ + f₁·τ."""
        g0, g1 = self.T.T @ f0, self.T.T @ f1
        static0, static1 = self.S @ f0, self.S @ f1
        if self.real:
            q0 = self.PhiTM @ x0[self.a]
            qd0 = self.PhiTM @ v0[self.a]
            p0, p1 = self.Phi.T @ g0, self.Phi.T @ g1
            w2 = self.w2
            osc = w2 > 0
            w = np.sqrt(w2[osc])
            lam = 1j * w
            c = (q0[osc] - p0[osc] / w2[osc]) - 1j * (qd0[osc] - p1[osc] / w2[osc]) / w
            Q = np.zeros((4, w2.size))
            Q[0, osc], Q[1, osc] = p0[osc] / w2[osc], p1[osc] / w2[osc]
            rb = ~osc
            Q[0, rb], Q[1, rb], Q[2, rb], Q[3, rb] = q0[rb], qd0[rb], p0[rb] / 2, p1[rb] / 6
            Za = c[:, None] * self.Phi[:, osc].T
            Pa = Q @ self.Phi.T
        else:
            y0 = np.concatenate([x0[self.a], v0[self.a], x0[self.d]])
            lam = self.lam_c
            z0 = self.Vi @ y0
            h0 = self.Vi @ (self.B @ g0)
            h1 = self.Vi @ (self.B @ g1)
            beta = -h1 / lam
            alpha = (beta - h0) / lam
            Vx = self.V[self.xrows]
            Za = (z0 - alpha)[:, None] * Vx.T
            Pa = np.zeros((4, self.xrows.size))
            Pa[0] = (Vx @ alpha).real
            Pa[1] = (Vx @ beta).real
        Z = Za @ self.T.T
        P = Pa @ self.T.T
        P[0] += static0
        P[1] += static1
        return Trajectory(lam, Z, P)


# ---------------------------------------------------------------------------------------------
# Event location
# ---------------------------------------------------------------------------------------------


def first_zero(sig, tau_end, at_event=False, max_iter=2_000_000):
    """First τ in (0, τ_end] where `sig`, which is ≥ 0 just after τ = 0, falls to 0; None if it
    does not. Conservative advancement: from τ with value e ≥ 0, slope e′ and the bound
    |f″| ≤ B = Σ|cᵢ||λᵢ|²·exp(Re λᵢ·τ) + max|p″|, no root lies before the positive root s* of
    e + e′s − Bs²/2; step s* and repeat. Near a simple root this converges quadratically.

    `at_event`: the phase starts at an event, where the function is 0 up to rounding (the
    modal reconstruction of the state); whether it persists is decided by the sign of the first
    of (f, f′, f″) that exceeds 1e-9 of its scale (Σ|cᵢ||λᵢ|ᵏ + polynomial), the same test that
    ended the previous phase with the opposite sign, so no zero-length phases can alternate."""
    lam, c = sig.lam, sig.c
    cl = c * lam
    b2c = np.abs(c) * np.abs(lam) ** 2
    re = lam.real
    p = sig.p
    P = np.polynomial.polynomial
    pd = P.polyder(p) if p.size > 1 else np.zeros(1)
    pdd = P.polyder(pd) if pd.size > 1 else np.zeros(1)

    def ev(t):
        ex = np.exp(lam * t)
        return (ex @ c).real + P.polyval(t, p), (ex @ cl).real + P.polyval(t, pd)

    powers = tau_end ** np.arange(p.size)
    s0 = np.sum(np.abs(c)) + np.sum(np.abs(p) * powers) + 1e-300
    s1 = np.sum(np.abs(cl)) + np.sum(np.abs(pd) * powers[: pd.size]) + 1e-300
    s2 = np.sum(b2c) + np.sum(np.abs(pdd) * powers[: pdd.size]) + 1e-300
    tau = 0.0
    e, de = ev(0.0)
    if at_event:
        d2 = (c @ (lam * lam)).real + pdd[0]
        for val, sc in ((e, s0), (de, s1), (d2, s2)):
            if abs(val) > 1e-9 * sc:
                if val < 0:
                    return 0.0
                break
        if abs(e) <= 1e-9 * s0 and abs(de) <= 1e-9 * s1:
            tau = min(1e-12, 0.5 * tau_end)  # leave a tangential start
    elif e < -1e-9 * s0:
        return 0.0
    for _ in range(max_iter):
        e, de = ev(tau)
        if e < 0.0:
            if tau > 0.0:
                return tau  # at a root, to rounding
            e = 0.0
        b2 = b2c @ np.exp(re * tau) + max(abs(P.polyval(tau, pdd)), abs(P.polyval(tau_end, pdd)))
        if b2 > 0:
            disc = de * de + 2.0 * b2 * e
            s = (de + np.sqrt(disc)) / b2 if de >= 0 else 2.0 * e / (np.sqrt(disc) - de)
        else:
            s = np.inf if de >= 0 else e / -de
        if tau + s >= tau_end:
            return None
        if s < 1e-15 * max(1.0, tau) + 1e-16:
            if de < 0:  # a crossing
                return tau + s
            s = 1e-13  # grazing: step over the touch
        tau += s
    raise RuntimeError("event search did not converge")


def refine_max(sig, lo, hi):
    """Maximum of |sig| on [lo, hi] by bounded Brent search to 1e-7 of the interval (the value is
    then exact to ~(ω·1e-7·(hi − lo))², far below rounding for the intervals used): (τ, |value|)."""
    f = lambda t: -abs(float(sig(t)))  # noqa: E731
    r = scipy.optimize.minimize_scalar(f, bounds=(lo, hi), method="bounded", options={"xatol": 1e-15 + 1e-7 * (hi - lo)})
    cands = [(lo, -f(lo)), (hi, -f(hi)), (r.x, -r.fun)]
    return max(cands, key=lambda c: c[1])


# ---------------------------------------------------------------------------------------------
# Piecewise-linear contact model and its driver
# ---------------------------------------------------------------------------------------------


@dataclass
class Output:
    """A linear output y = Dx·x + Dv·ẋ + Da·ẍ + ga·a_g + const (ẍ relative, so ga carries the
    rigid-ground acceleration of every mass the output's inertia terms involve)."""

    Dx: np.ndarray | None = None
    Dv: np.ndarray | None = None
    Da: np.ndarray | None = None
    ga: float = 0.0
    const: float = 0.0
    Fw: float = 0.0  # + Fw·F while in contact (a contact force applied directly to a DOF combination)


@dataclass
class ContactModel:
    """Everything the driver needs: M, C, K over the free DOFs (relative to the ground), the
    load vector l (f = −l·a_g), the contact (δ = x[slab] − d·x − gap), outputs per configuration
    (name → Output; the contact-force output "F" is added by the driver) and the energy form."""

    M: np.ndarray
    C: np.ndarray
    K: np.ndarray
    load: np.ndarray
    slab: int
    d: np.ndarray
    k_c: float
    c_c: float
    gap: float
    outputs: dict
    labels: list = field(default_factory=list)

    def matrices(self, closed):
        if not closed:
            return self.M, self.C, self.K
        e = -self.d.copy()
        e[self.slab] += 1.0
        return self.M, self.C + self.c_c * np.outer(e, e), self.K + self.k_c * np.outer(e, e)

    def contact_rows(self):
        e = -self.d.copy()
        e[self.slab] += 1.0
        return e


@dataclass
class Phase:
    """A stretch between contact events (closed: an impact); record samples do not split it."""

    t0: float
    t1: float
    closed: bool
    peak: float = 0.0  # peak contact force within a closed phase (N)
    impulse: float = 0.0  # ∫F dt over the phase (N·s)


@dataclass
class Result:
    """Histories on the grid t (s); `phases` lists every linear phase; impacts are the closed
    ones. `integral[name]` is ∫₀ᵗ y dt on the grid (exact), `peak[name]` the exact max |y|."""

    t: np.ndarray
    series: dict
    integral: dict
    peak: dict
    phases: list
    energy: list  # (t, energy) at every phase boundary (J)
    state_end: tuple

    @property
    def impacts(self):
        return [p for p in self.phases if p.closed]

    def impulse(self):
        return float(sum(p.impulse for p in self.impacts))

    def window_peak(self, name, window):
        """Peak |ȳ| of the running average ȳ(t) = (1/T)∫_{t−T}^{t} y dt' (y taken as 0 before
        t = 0), T = `window` s, evaluated on the grid (T must be a multiple of the grid step)."""
        dt = self.t[1] - self.t[0]
        w = int(round(window / dt))
        if abs(w * dt - window) > 1e-9 * window:
            raise ValueError("window must be a multiple of the output step")
        I = self.integral[name]
        prev = np.concatenate([np.zeros(w), I[:-w]]) if w < I.size else np.zeros_like(I)
        return float(np.max(np.abs(I - prev)) / window)

    def summary(self):
        imp = self.impacts
        return {
            "n_impacts": len(imp),
            "first_duration": imp[0].t1 - imp[0].t0 if imp else 0.0,
            "contact_time": float(sum(p.t1 - p.t0 for p in imp)),
            "span": imp[-1].t1 - imp[0].t0 if imp else 0.0,
            "impulse": self.impulse(),
            "peak_F": max((p.peak for p in imp), default=0.0),
        }


def _stack(sigs):
    """Coefficient matrices (m × k) and polynomial matrix (deg+1 × k) of signals of one phase."""
    Cm = np.stack([g.c for g in sigs], axis=1)
    deg = max(g.p.size for g in sigs)
    Pm = np.stack([np.pad(g.p, (0, deg - g.p.size)) for g in sigs], axis=1)
    return Cm, Pm


def _sample(lam, Cm, Pm, taus, chunk=4096):
    out = np.empty((taus.size, Cm.shape[1]))
    for i in range(0, taus.size, chunk):
        tt = taus[i : i + chunk]
        E = np.exp(np.multiply.outer(tt, lam))
        out[i : i + chunk] = (E @ Cm).real + np.polynomial.polynomial.polyval(tt, Pm).T
    return out


def simulate(model: ContactModel, x0, v0, t_end, dt_out, ground=None, energy=True, closed0=False):
    """Run the piecewise-linear model from (x₀, v₀) to t_end. `ground` = (t_samples, a_samples)
    (m/s², linear between samples, 0 after the last). Histories are sampled every dt_out; the
    running integrals at the samples are exact; peaks are exact maxima (sampled on the grid and
    on 33 points per phase, then refined by a bounded Brent search around the largest)."""
    nt = int(round(t_end / dt_out)) + 1
    tgrid = np.arange(nt) * dt_out
    e_c = model.contact_rows()
    names = list(model.outputs) + ["F"]
    series = {k: np.zeros(nt) for k in names}
    integ = {k: np.zeros(nt) for k in names}
    running = np.zeros(len(names))
    peak = {k: 0.0 for k in names}
    phase_cache = {}
    breaks = [t_end]
    ag_t = ag_a = None
    if ground is not None:
        ag_t, ag_a = (np.asarray(g, dtype=float) for g in ground)
        breaks = sorted(set([float(t) for t in ag_t if 0 < t < t_end] + [t_end]))

    def a_g(t):
        if ag_t is None:
            return 0.0, 0.0
        k = np.searchsorted(ag_t, t + 1e-12, side="right") - 1
        if k < 0 or k >= ag_t.size - 1:
            return 0.0, 0.0
        slope = (ag_a[k + 1] - ag_a[k]) / (ag_t[k + 1] - ag_t[k])
        return ag_a[k] + slope * (t - ag_t[k]), slope

    M0, _, K0 = model.matrices(False)

    def energy_of(x, v, closed):
        E = 0.5 * v @ M0 @ v + 0.5 * x @ K0 @ x
        if closed:
            dl = e_c @ x - model.gap
            E += 0.5 * model.k_c * dl * dl
        return float(E)

    x = np.array(x0, dtype=float)
    v = np.array(v0, dtype=float)
    t = 0.0
    closed = closed0
    phases = []
    energies = [(0.0, energy_of(x, v, closed))] if energy else []
    k_next = 0  # next grid index to fill
    ib = 0
    watch_release = False  # open with δ > 0 after a dashpot release
    at_event = False
    continued_from_event = True
    zero_run = 0
    while t < t_end - 1e-15:
        while breaks[ib] <= t + 1e-15:
            ib += 1
        seg = breaks[ib] - t
        if closed not in phase_cache:
            phase_cache[closed] = LinearPhase(*model.matrices(closed))
        ph = phase_cache[closed]
        ag0, ag1 = a_g(t)
        f0 = -model.load * ag0
        f1 = -model.load * ag1
        if closed:
            f0 = f0 + model.k_c * model.gap * e_c
        tr = ph.trajectory(x, v, f0, f1)
        delta = tr.signal(Dx=e_c, const=-model.gap)
        trial = tr.signal(Dx=model.k_c * e_c, Dv=model.c_c * e_c, const=-model.k_c * model.gap)
        neg = lambda g: Signal(g.lam, -g.c, -g.p)  # noqa: E731
        if closed:
            tau = first_zero(trial, seg, at_event)
            event = "release" if tau is not None else None
        elif watch_release:
            tau_c = first_zero(neg(trial), seg, at_event)
            tau_o = first_zero(delta, seg if tau_c is None else tau_c)
            tau, event = (tau_o, "reopen") if tau_o is not None else (tau_c, "contact" if tau_c is not None else None)
        else:
            tau = first_zero(neg(delta), seg, at_event)
            event = "contact" if tau is not None else None
        at_event = event is not None
        zero_run = zero_run + 1 if tau == 0.0 else 0
        if zero_run > 100:
            raise RuntimeError(f"zero-length phases alternate at t = {t}")
        tau_stop = seg if tau is None else tau
        t1 = t + tau_stop
        last = tau is None and ib == len(breaks) - 1
        k_end = int(np.searchsorted(tgrid, t1 - 1e-13, side="left")) if not last else nt
        ks = np.arange(k_next, k_end)
        taus = np.clip(tgrid[ks] - t, 0.0, tau_stop)
        F = trial if closed else Signal(trial.lam, 0 * trial.c, [0.0])
        sigs = []
        for name in names[:-1]:
            o = model.outputs[name]
            g = tr.signal(o.Dx, o.Dv, o.Da, o.const, o.ga, (ag0, ag1))
            if o.Fw and closed:
                g = g + Signal(F.lam, o.Fw * F.c, o.Fw * F.p)
            sigs.append(g)
        sigs.append(F)
        ints = [g.integral() for g in sigs]
        Cm, Pm = _stack(sigs)
        Ci, Pi = _stack(ints)
        vals = _sample(tr.lam, Cm, Pm, taus)
        ivals = _sample(tr.lam, Ci, Pi, np.append(taus, tau_stop))
        cand = np.linspace(0.0, tau_stop, 33)
        cvals = np.abs(_sample(tr.lam, Cm, Pm, cand))
        # |y''| bound per output, for deciding where a peak between samples can still beat the
        # running peak: max|y| ≤ sample + B·g²/8 within a gap g of the sample; the largest
        # samples that can are refined (Brent between their neighbours)
        b2 = np.abs(Cm).T @ (np.abs(tr.lam) ** 2)
        if Pm.shape[0] > 2:
            b2 = b2 + np.abs(2 * Pm[2])
        if Pm.shape[0] > 3:
            b2 = b2 + np.abs(6 * Pm[3]) * tau_stop
        allt = np.concatenate([taus, cand])
        order = np.argsort(allt, kind="stable")
        ts = allt[order]
        gaps = np.diff(ts)
        gap = np.maximum(np.concatenate([[0.0], gaps]), np.concatenate([gaps, [0.0]]))
        for j, name in enumerate(names):
            series[name][ks] = vals[:, j]
            integ[name][ks] = running[j] + ivals[:-1, j]
            vs = np.concatenate([np.abs(vals[:, j]), cvals[:, j]])[order]
            best = max(peak[name], float(vs.max()))
            slack = b2[j] * gap**2 / 8
            for i in np.argsort(-vs)[:4]:  # the 4 largest samples at most: cost stays bounded
                if vs[i] + slack[i] <= best:
                    continue
                lo, hi = ts[max(i - 1, 0)], ts[min(i + 1, ts.size - 1)]
                if hi > lo:
                    best = max(best, refine_max(sigs[j], lo, hi)[1])
            peak[name] = best
        running += ivals[-1]
        k_next = k_end
        P = Phase(t, t1, closed)
        if closed and tau_stop > 0.0:
            P.impulse = float(ivals[-1, -1])
            j = int(np.argmax(cvals[:, -1]))
            P.peak = refine_max(F, cand[max(j - 1, 0)], cand[min(j + 1, 32)])[1]
            P.peak = max(P.peak, float(np.max(np.abs(vals[:, -1]), initial=0.0)))
        if tau_stop > 0.0:
            if phases and not continued_from_event and phases[-1].closed == closed and phases[-1].t1 == t:
                # the same contact (or gap) continued across a record sample: one phase
                prev = phases[-1]
                prev.t1, prev.peak, prev.impulse = t1, max(prev.peak, P.peak), prev.impulse + P.impulse
            else:
                phases.append(P)
        continued_from_event = event is not None
        x = tr.x(tau_stop)
        v = tr.x(tau_stop, 1)
        t = t1
        if event == "contact":
            closed, watch_release = True, False
        elif event == "release":
            closed = False
            watch_release = model.c_c > 0 and float(e_c @ x - model.gap) > 0
        elif event == "reopen":
            watch_release = False
        if energy:
            energies.append((t, energy_of(x, v, closed)))
    return Result(tgrid, series, integ, peak, phases, energies, (x, v))


# ---------------------------------------------------------------------------------------------
# The two buildings
# ---------------------------------------------------------------------------------------------


@dataclass
class Frame:
    """The struck building A (planar): floor masses m_i (kg, floors 1..N), storey heights h_i
    (m), columns per storey n_c, and one column section: E (Pa), I (m⁴), ρA (kg/m, 0 for
    massless columns). Optional Rayleigh damping C = a₀M + a₁K of the whole frame."""

    masses: list
    heights: list
    n_columns: list
    E: float
    I: float
    rhoA: float = 0.0
    rayleigh: tuple = (0.0, 0.0)

    @property
    def EI(self):
        return self.E * self.I

    def k_column(self, i):
        return 12.0 * self.EI / self.heights[i - 1] ** 3


@dataclass
class Neighbour:
    """The neighbour B: a shear building of floor masses (kg) and storey stiffnesses (N/m; a
    single floor is a SDOF, a zero spring a free mass); `floor` is the contact floor (1-based,
    default the roof). Optional Rayleigh damping (a₀, a₁)."""

    masses: list
    stiffness: list
    floor: int | None = None
    rayleigh: tuple = (0.0, 0.0)

    @property
    def contact_floor(self):
        return self.floor or len(self.masses)


@dataclass
class Impact:
    """The contact: struck storey (1-based, between floors i−1 and i), ξ ∈ (0, 1), contact
    stiffness k_c (N/m), dashpot c_c (N·s/m), gap (m); the impact test's approach speed v0
    (m/s) of the neighbour's contact floor and how the neighbour moves: "mode1" (its first mode
    shape, scaled to v0 at the contact floor), "uniform" (all floors at v0) or "slab"."""

    storey: int
    xi: float
    k_c: float
    c_c: float = 0.0
    gap: float = 0.0
    v0: float = 0.5
    init: str = "mode1"


def _shear_building(masses, stiffness):
    n = len(masses)
    K = np.zeros((n, n))
    for i, k in enumerate(stiffness):
        K[i, i] += k
        if i > 0:
            K[i - 1, i - 1] += k
            K[i - 1, i] -= k
            K[i, i - 1] -= k
    return np.diag(np.asarray(masses, dtype=float)), K


class _Assembly:
    """DOF bookkeeping: DOF 0 is the ground's lateral displacement (fixed; kept so the rigid
    translation r and the consistent-mass couplings to the ground are exact), others are added
    with labels; rotations at the floors are fixed and are not DOFs."""

    def __init__(self):
        self.labels = ["ground"]
        self.lateral = [True]
        self.triplets_K, self.triplets_M = [], []

    def add(self, label, lateral):
        self.labels.append(label)
        self.lateral.append(lateral)
        return len(self.labels) - 1

    def add_matrix(self, which, dofs, mat):
        for a, da in enumerate(dofs):
            if da is None:
                continue
            for b, db in enumerate(dofs):
                if db is None or mat[a, b] == 0.0:
                    continue
                which.append((da, db, mat[a, b]))

    def dense(self):
        n = len(self.labels)
        K = np.zeros((n, n))
        M = np.zeros((n, n))
        for i, j, v in self.triplets_K:
            K[i, j] += v
        for i, j, v in self.triplets_M:
            M[i, j] += v
        return M, K


def _column(asm, bottom, top, h, EI, rhoA, z_nodes, tag):
    """Assemble one explicit column (bundle) between floor DOFs `bottom` and `top` (rotations
    clamped) with nodes at `z_nodes` (0 … h). Returns the element DOF lists."""
    nodes = [(bottom, None)]
    for k, z in enumerate(z_nodes[1:-1], start=1):
        nodes.append((asm.add(f"{tag} w@{z:.4f}", True), asm.add(f"{tag} θ@{z:.4f}", False)))
    nodes.append((top, None))
    elems = []
    for e in range(len(z_nodes) - 1):
        L = z_nodes[e + 1] - z_nodes[e]
        dofs = [nodes[e][0], nodes[e][1], nodes[e + 1][0], nodes[e + 1][1]]
        asm.add_matrix(asm.triplets_K, dofs, beam_stiffness(EI, L))
        if rhoA > 0:
            asm.add_matrix(asm.triplets_M, dofs, beam_mass(rhoA, L))
        elems.append((dofs, L))
    return nodes, elems


def struck_mesh(h, xi, n_e):
    """Node heights of the struck column: n₁ = max(1, round(ξ·n_e)) equal elements below the
    contact node and n_e − n₁ (≥ 1) above, so the contact height is a node exactly."""
    if n_e < 2:
        raise ValueError("the struck column needs at least 2 elements")
    n1 = min(max(1, int(round(xi * n_e))), n_e - 1)
    a = xi * h
    return np.concatenate([np.linspace(0.0, a, n1 + 1), np.linspace(a, h, n_e - n1 + 1)[1:]]), n1


def _finish(asm, frame_dofs, nb_dofs, frame, nb):
    """Dense matrices over the free DOFs, load vector l = M_free,all·r, Rayleigh damping."""
    M, K = asm.dense()
    lat = np.array(asm.lateral, dtype=float)
    l_all = M @ lat
    free = np.arange(1, len(asm.labels))
    Mf, Kf = M[np.ix_(free, free)], K[np.ix_(free, free)]
    C = np.zeros_like(Kf)
    # Rayleigh damping per building (each on its own DOFs)
    for dofs, (a0, a1) in ((frame_dofs, frame.rayleigh), (nb_dofs, nb.rayleigh)):
        idx = np.array([d - 1 for d in dofs])
        if a0 or a1:
            C[np.ix_(idx, idx)] += a0 * Mf[np.ix_(idx, idx)] + a1 * Kf[np.ix_(idx, idx)]
    return Mf, C, Kf, l_all[free], lat


def _neighbour_dofs(asm, nb):
    floors = [asm.add(f"B floor {i + 1}", True) for i in range(len(nb.masses))]
    for i, (m, k) in enumerate(zip(nb.masses, nb.stiffness)):
        asm.triplets_M.append((floors[i], floors[i], m))
        below = 0 if i == 0 else floors[i - 1]
        if k:
            dofs = [below, floors[i]]
            asm.add_matrix(asm.triplets_K, dofs, k * np.array([[1.0, -1.0], [-1.0, 1.0]]))
    return floors


def _drift_outputs(n, floorsA, floorsB):
    outs = {}
    for tag, floors in (("A", floorsA), ("B", floorsB)):
        for i, f in enumerate(floors):
            D = np.zeros(n)
            D[f - 1] += 1.0
            if i > 0:
                D[floors[i - 1] - 1] -= 1.0
            outs[f"drift_{tag}{i + 1}"] = Output(Dx=D)
    return outs


def initial_state(model_labels, nb, imp, floorsB):
    """x₀ = 0, v₀ on the neighbour's floors per `imp.init` (the struck building at rest)."""
    n = len(model_labels)
    v0 = np.zeros(n)
    idx = np.array(floorsB) - 1
    jc = nb.contact_floor - 1
    if imp.init == "uniform":
        shape = np.ones(len(floorsB))
    elif imp.init == "slab":
        shape = np.zeros(len(floorsB))
        shape[jc] = 1.0
    elif imp.init == "mode1":
        Mb, Kb = _shear_building(nb.masses, nb.stiffness)
        _, V = scipy.linalg.eigh(Kb, Mb)
        shape = V[:, 0] / V[jc, 0]
    else:
        raise ValueError(imp.init)
    v0[idx] = imp.v0 * shape
    return np.zeros(n), v0


def _floor_dofs(asm: "_Assembly", frame: Frame, nb: Neighbour) -> tuple[list[int], list[int]]:
    """The floor DOFs of the struck building (with their masses) and of the neighbour."""
    floors = [asm.add(f"A floor {i + 1}", True) for i in range(len(frame.masses))]
    for dof, m in zip(floors, frame.masses):
        asm.triplets_M.append((dof, dof, m))
    return floors, _neighbour_dofs(asm, nb)


def build_fe(frame: Frame, nb: Neighbour, imp: Impact, n_e: int, other_columns="lumped"):
    """The FE reference: returns (ContactModel, x₀, v₀). The struck column of storey
    `imp.storey` is explicit with n_e Hermite elements and a node at ξ; the other columns per
    `other_columns` (see the module docstring). Outputs: drifts of both buildings, the struck
    column's end forces on the floors V_bot, V_top (N) and end moments M_bot, M_top (N·m),
    from the end elements' K_e·u_e + M_e·ü_e (absolute accelerations)."""
    asm = _Assembly()
    N = len(frame.masses)
    floorsA, floorsB = _floor_dofs(asm, frame, nb)
    frame_dofs = list(floorsA)
    struck = None
    for i in range(1, N + 1):
        h = frame.heights[i - 1]
        bottom = 0 if i == 1 else floorsA[i - 2]
        top = floorsA[i - 1]
        n_other = frame.n_columns[i - 1] - (1 if i == imp.storey else 0)
        before = len(asm.labels)
        if i == imp.storey:
            z, n1 = struck_mesh(h, imp.xi, n_e)
            nodes, elems = _column(asm, bottom, top, h, frame.EI, frame.rhoA, z, f"A s{i} struck")
            struck = (nodes, elems, n1)
        if n_other:
            if other_columns == "beam":
                _column(asm, bottom, top, h, n_other * frame.EI, n_other * frame.rhoA, np.linspace(0, h, n_e + 1), f"A s{i} others")
            elif other_columns in ("lumped", "guyan"):
                k = n_other * 12.0 * frame.EI / h**3
                asm.add_matrix(asm.triplets_K, [bottom, top], k * np.array([[1.0, -1.0], [-1.0, 1.0]]))
                m = n_other * frame.rhoA * h
                if m and other_columns == "lumped":
                    asm.triplets_M += [(bottom, bottom, m / 2), (top, top, m / 2)]
                elif m:  # consistent mass of the storey shapes (1 − s, s)
                    asm.add_matrix(asm.triplets_M, [bottom, top], m * np.array([[13 / 35, 9 / 70], [9 / 70, 13 / 35]]))
            else:
                raise ValueError(other_columns)
        frame_dofs += list(range(before, len(asm.labels)))
    # the ground's own lumped mass terms land on DOF 0 and are dropped with it
    Mf, C, Kf, load, lat = _finish(asm, frame_dofs, floorsB, frame, nb)
    n = Mf.shape[0]
    nodes, elems, n1 = struck
    d = np.zeros(n)
    d[nodes[n1][0] - 1] = 1.0
    outs = _drift_outputs(n, floorsA, floorsB)
    for name, (dofs, L), row in (("V_bot", elems[0], 0), ("M_bot", elems[0], 1), ("V_top", elems[-1], 2), ("M_top", elems[-1], 3)):
        Ke = beam_stiffness(frame.EI, L)
        Me = beam_mass(frame.rhoA, L)
        Dx, Da = np.zeros(n), np.zeros(n)
        ga = 0.0
        for b, db in enumerate(dofs):
            if db is None:
                continue
            if db == 0:  # the ground node: relative displacement 0, absolute acceleration a_g
                ga -= Me[row, b]
                continue
            Dx[db - 1] -= Ke[row, b]
            Da[db - 1] -= Me[row, b]
            ga -= Me[row, b] * lat[db]
        outs[name] = Output(Dx=Dx, Da=Da if frame.rhoA > 0 else None, ga=ga)
    model = ContactModel(Mf, C, Kf, load, floorsB[nb.contact_floor - 1] - 1, d, imp.k_c, imp.c_c, imp.gap, outs, asm.labels[1:])
    x0, v0 = initial_state(asm.labels[1:], nb, imp, floorsB)
    return model, x0, v0


def build_reduced(frame: Frame, nb: Neighbour, imp: Impact, variant="b", n_modes=0, residual=True, form="cb", extra_flex=0.0):
    """The reduced model as pound would implement it (planar):

    * floors of both buildings as lumped DOFs; every storey's stiffness n_c·12EI/h³ (struck
      column included); the other columns' mass lumped half to each end floor (as
      `build_fe(other_columns="lumped")`);
    * the slab meets the storey's outline at ξ: u(ξ) = u_(i−1)·(1 − s) + u_i·s, s = s(ξ), and
      the force goes to the floors with the same weights (virtual work);
    * variant "a": the contact spring k_c on the outline directly (no local flexibility);
      variant "b": k_c in series with the struck column's point-load flexibility
      a³b³/(3EIh³) through a massless node (for ρA > 0 the struck column's mass enters as the
      consistent mass of the storey shapes, i.e. Craig–Bampton with no interior mode);
      variant "c": Craig–Bampton: the storey shapes (1 − s, s) plus `n_modes` clamped–clamped
      modes φ_k with modal mass ρAh, stiffness EI·(β_kL)⁴/h³, mass couplings
      ρAh·∫ψ_bφ_k dξ to the end floors, contact point Σψ_b(ξ)u_b + Σφ_k(ξ)q_k; with
      `residual` the truncated modes' static flexibility a³b³/(3EIh³) − Σφ_k(ξ)²h³/(EIβ_k⁴)
      stays in series with k_c (so n_modes = 0 is variant "b").
    * `form="sprung"`: the same model in the coordinates q′_k = q_k + Σ_b (M_qb/m_k)·u_b in which
      the modal masses decouple from the floors (each local mode is a mass m_k on a spring k_k
      attached to the floors with weights M_qb/m_k); `form="lumped"`: that, with the
      remaining floor mass block lumped by rows (a diagonal mass matrix).
    * `extra_flex` (m/N) is added to the series flexibility (e.g. the point load's shear
      deformation a·b/(κGA·h), for the study of the idealisation's limits).
    """
    if variant not in ("a", "b", "c"):
        raise ValueError(variant)
    if variant != "c":
        n_modes = 0
    if n_modes and frame.rhoA <= 0:
        raise ValueError("local modes need ρA > 0")
    asm = _Assembly()
    N = len(frame.masses)
    floorsA, floorsB = _floor_dofs(asm, frame, nb)
    i = imp.storey
    h = frame.heights[i - 1]
    EI, rhoA = frame.EI, frame.rhoA
    for j in range(1, N + 1):
        hj = frame.heights[j - 1]
        bot = 0 if j == 1 else floorsA[j - 2]
        k = frame.n_columns[j - 1] * 12.0 * EI / hj**3
        asm.add_matrix(asm.triplets_K, [bot, floorsA[j - 1]], k * np.array([[1.0, -1.0], [-1.0, 1.0]]))
        n_other = frame.n_columns[j - 1] - (1 if j == i else 0)
        m = n_other * rhoA * hj / 2
        if m:
            asm.triplets_M += [(bot, bot, m), (floorsA[j - 1], floorsA[j - 1], m)]
    b = [0 if i == 1 else floorsA[i - 2], floorsA[i - 1]]
    mc = rhoA * h
    Mbb = mc * np.array([[13 / 35, 9 / 70], [9 / 70, 13 / 35]])
    if rhoA > 0:
        asm.add_matrix(asm.triplets_M, b, Mbb)
    s = float(storey_shape(imp.xi))
    psi = np.array([1 - s, s])
    qs, data = [], []
    for kmode in range(1, n_modes + 1):
        dk = clamped_modal_data(kmode, imp.xi)
        q = asm.add(f"q{kmode}", False)
        qs.append(q)
        data.append(dk)
        asm.triplets_M.append((q, q, mc))
        asm.triplets_K.append((q, q, EI * dk["beta4"] / h**3))
        for bi, bd in enumerate(b):
            asm.triplets_M += [(q, bd, mc * dk["bb"][bi]), (bd, q, mc * dk["bb"][bi])]
    # the contact point o·x and the residual spring
    n_all = len(asm.labels)
    o = np.zeros(n_all)
    o[b] += psi
    for q, dk in zip(qs, data):
        o[q] += dk["phi_xi"]
    flex = point_load_flexibility(EI, h, imp.xi) - sum(dk["phi_xi"] ** 2 * h**3 / (EI * dk["beta4"]) for dk in data) + extra_flex
    w = None
    if variant in ("b", "c") and (residual or not n_modes):
        w = asm.add("node", True)
        o = np.append(o, 0.0)
        e = -o.copy()
        e[w] += 1.0
        asm.add_matrix(asm.triplets_K, list(range(len(e))), np.outer(e, e) / flex)
    M_all, K_all = asm.dense()
    lat = np.array(asm.lateral, dtype=float)
    lat[qs] = 0.0
    if w is not None:
        lat[w] = 0.0  # massless: no inertia, and it follows the outline anyway
    free = np.arange(1, len(asm.labels))
    n = free.size
    # outputs in Craig–Bampton coordinates (all DOFs incl. ground), then restricted
    outs_all = {}
    Fres = np.zeros(len(asm.labels))
    if w is not None:
        Fres[w] += 1.0 / flex
        Fres[: o.size] -= o / flex
    kcol = 12.0 * EI / h**3
    a_, b_ = imp.xi * h, h - imp.xi * h
    Mth = mc * h / 420.0 * np.array([[22.0, 13.0], [-13.0, -22.0]])  # rotation rows × (u_bot, u_top)
    for name, row in (("V_bot", 0), ("V_top", 1), ("M_bot", 0), ("M_top", 1)):
        Dx = np.zeros(len(asm.labels))
        Da = np.zeros(len(asm.labels))
        if name[0] == "V":
            Dx[b] -= kcol * np.array([[1.0, -1.0], [-1.0, 1.0]])[row]
            Da[b] -= Mbb[row]
            for q, dk in zip(qs, data):
                Da[q] -= mc * dk["bb"][row]
            wt = psi[row]
        else:
            Dx[b] += 6.0 * EI / h**2 * np.array([-1.0, 1.0])
            Da[b] -= Mth[row]
            for q, dk in zip(qs, data):
                Da[q] -= mc * h * dk["th"][row]
            wt = (a_ * b_**2 / h**2) if row == 0 else (-(a_**2) * b_ / h**2)
        outs_all[name] = (Dx, Da, wt)
    slab = floorsB[nb.contact_floor - 1]
    if w is not None:
        dvec = np.zeros(len(asm.labels))
        dvec[w] = 1.0
    else:
        dvec = o.copy()
    # transformation to the chosen form (free DOFs): x_cb = T·x_new
    T = np.eye(n)
    if form in ("sprung", "lumped") and qs:
        for q, dk in zip(qs, data):
            for bi, bd in enumerate(b):
                if bd:
                    T[q - 1, bd - 1] = -dk["bb"][bi]
    elif form not in ("cb", "sprung", "lumped"):
        raise ValueError(form)
    Mf = T.T @ M_all[np.ix_(free, free)] @ T
    Kf = T.T @ K_all[np.ix_(free, free)] @ T
    load = T.T @ (M_all @ lat)[free]
    if form == "lumped":
        r_new = np.linalg.solve(T, lat[free])
        ground_part = T.T @ (M_all[free, 0] * lat[0])
        fl = [f - 1 for f in floorsA + floorsB]
        blk = Mf[np.ix_(fl, fl)]
        Mf[np.ix_(fl, fl)] = np.diag(blk.sum(axis=1))
        load = Mf @ r_new + ground_part
    outs = _drift_outputs(n, floorsA, floorsB)
    for name, (Dx, Da, wt) in outs_all.items():
        Dx = Dx + wt * Fres
        ga = float(Da @ lat)
        outs[name] = Output(Dx=T.T @ Dx[free], Da=(T.T @ Da[free]) if rhoA > 0 else None, ga=ga, Fw=wt if w is None else 0.0)
    C = np.zeros_like(Kf)
    if any(frame.rayleigh):
        a0, a1 = frame.rayleigh
        idx = [k for k in range(n) if k not in [f - 1 for f in floorsB]]
        C[np.ix_(idx, idx)] += a0 * Mf[np.ix_(idx, idx)] + a1 * Kf[np.ix_(idx, idx)]
    if any(nb.rayleigh):
        a0, a1 = nb.rayleigh
        idx = [f - 1 for f in floorsB]
        C[np.ix_(idx, idx)] += a0 * Mf[np.ix_(idx, idx)] + a1 * Kf[np.ix_(idx, idx)]
    model = ContactModel(Mf, C, Kf, load, slab - 1, T.T @ dvec[free], imp.k_c, imp.c_c, imp.gap, outs, asm.labels[1:])
    x0, v0 = initial_state(asm.labels[1:], nb, imp, floorsB)
    model.meta = {"flex_residual": flex, "k_res": 1 / flex if w is not None else np.inf, "modes": data}
    return model, x0, v0


# ---------------------------------------------------------------------------------------------
# Small helpers for tests and the study
# ---------------------------------------------------------------------------------------------


def clamped_column_frequencies(EI, rhoA, h, n_e, count=3):
    """Lowest `count` circular frequencies (rad/s) of one column clamped at both (fixed) ends,
    from n_e equal Hermite elements with consistent mass."""
    asm = _Assembly()
    z = np.linspace(0.0, h, n_e + 1)
    _column(asm, 0, 0, h, EI, rhoA, z, "c")
    M, K = asm.dense()
    free = np.arange(1, len(asm.labels))
    w2 = scipy.linalg.eigh(K[np.ix_(free, free)], M[np.ix_(free, free)], eigvals_only=True)
    return np.sqrt(w2[:count])


def static_point_load(EI, h, xi, n_e, P=1.0):
    """Static solution of one FE column with clamped, non-moving ends and a point load P at ξ:
    (deflection under the load, end shears and moments as support reactions)."""
    asm = _Assembly()
    z, n1 = struck_mesh(h, xi, n_e)
    nodes, elems = _column(asm, 0, 0, h, EI, 0.0, z, "c")
    M, K = asm.dense()
    free = np.arange(1, len(asm.labels))
    f = np.zeros(len(asm.labels))
    f[nodes[n1][0]] = P
    u = np.zeros(len(asm.labels))
    u[free] = np.linalg.solve(K[np.ix_(free, free)], f[free])
    ends = []
    for (dofs, L), rows in ((elems[0], (0, 1)), (elems[-1], (2, 3))):
        ue = np.array([0.0 if dd is None or dd == 0 else u[dd] for dd in dofs])
        fe = beam_stiffness(EI, L) @ ue
        ends.append(-fe[list(rows)])  # force/moment of the column on its support
    return {"deflection": u[nodes[n1][0]], "V_bottom": ends[0][0], "M_bottom": ends[0][1], "V_top": ends[1][0], "M_top": ends[1][1]}
