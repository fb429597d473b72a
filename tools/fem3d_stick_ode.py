#!/usr/bin/env python3
"""fem3d_stick_ode.py - two-degree-of-freedom model of the elastic oblique impact
of a sphere (impact_refs.md 4.2): rigid sphere, Hertz normal force, Mindlin
tangential contact stiffness 8 G* a, optionally capped by Coulomb (|T| <= mu N).
An independent, model-dependent comparison for the 3D FE (docs/validation-3d.md),
not a reference value: the FE resolves the micro-slip annulus that this model
lumps into one tangential spring.
Tangential laws: incremental dT = 8 G* a dx (Mindlin), secant T = 8 G* a x.
Usage: fem3d_stick_ode.py [mu|inf] [v=10]  -> table for 30, 45, 60 degrees."""
import math
import sys


def run(angle, V=10.0, law="incremental", mu=math.inf, r=1.0, rho=2600.0, E=68.2e9, nu=0.25, e_n=None):
    m = 4 / 3 * math.pi * r**3 * rho
    I = 0.4 * m * r * r
    Es = E / (2 * (1 - nu * nu))
    G = E / (2 * (1 + nu))
    Gs = G / (2 * (2 - nu))
    k = 4 / 3 * Es * math.sqrt(r)
    vn, vt = V * math.cos(math.radians(angle)), V * math.sin(math.radians(angle))
    d, dd, x, T, vc, w = 0.0, vn, 0.0, 0.0, vt, 0.0
    tc = 2.94328 * (15 * m * vn * vn / (16 * Es * math.sqrt(r)))**0.4 / vn
    dt = tc / 200000
    started = False
    while True:
        dp = max(d, 0.0)
        a = math.sqrt(r * dp)
        N = k * dp**1.5
        kt = 8 * Gs * a
        if law == "secant":
            Tt = kt * x
        else:
            Tt = T
        if abs(Tt) > mu * N:
            Tt = math.copysign(mu * N, Tt)
            if law == "secant":
                x = Tt / kt if kt > 0 else 0.0
        T = Tt
        # symplectic Euler: forces at the current state, then velocities, then positions
        dd -= N / m * dt
        vc -= T / m * dt
        w += T * r / I * dt
        cpv = vc - w * r
        d += dd * dt
        x += cpv * dt
        if law != "secant":
            T += kt * cpv * dt
        if d > 0:
            started = True
        if started and d <= 0:
            break
    return vc / vt, w, (vc - w * r) / vt


if __name__ == "__main__":
    mu = float(sys.argv[1]) if len(sys.argv) > 1 else math.inf
    V = float(sys.argv[2]) if len(sys.argv) > 2 else 10
    for ang in (30, 45, 60):
        for law in ("incremental", "secant"):
            Rt, w, c = run(ang, V, law, mu)
            print(f"angle={ang} mu={mu} law={law} R_t={Rt:.4f} omega={w:.4f} cp_ratio={c:.4f}")
