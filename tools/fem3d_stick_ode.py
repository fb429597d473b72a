#!/usr/bin/env python3
"""fem3d_stick_ode.py - rigid sphere + Hertz normal contact + Mindlin no-slip
tangential contact (stiffness 8 G* a, no Coulomb cap): the f -> infinity limit
of the elastic oblique impact (impact_refs.md 4.2), as an independent check of
the FE's tangential compliance.  Two tangential laws: incremental
dT = 8 G* a dx (Mindlin, loading and unloading) and secant T = 8 G* a x.
Usage: fem3d_stick_ode.py angle_deg [v=10] [e_n=1] -> R_t, omega, contact-point velocity ratio."""
import math, sys
DEBUG = False

def run(angle, V=10.0, law="incremental", r=1.0, rho=2600.0, E=68.2e9, nu=0.25):
    m = 4/3*math.pi*r**3*rho
    I = 0.4*m*r*r
    Es = E/(2*(1-nu*nu))
    G = E/(2*(1+nu))
    Gs = G/(2*(2-nu))
    k = 4/3*Es*math.sqrt(r)
    mt = 1/(1/m + r*r/I)
    vn, vt = V*math.cos(math.radians(angle)), V*math.sin(math.radians(angle))
    # state: delta, ddelta, x (tangential contact-point disp.), xdot, T (tangential force), vcm_t, omega
    d, dd, x, xd, T, vc, w = 0.0, vn, 0.0, vt, 0.0, vt, 0.0
    dt = 1e-8
    t = 0.0
    def deriv(s):
        d, dd, x, xd, T, vc, w = s
        dp = max(d, 0.0)
        a = math.sqrt(r*dp)
        F = k*dp**1.5
        kt = 8*Gs*a
        if law == "secant":
            Tn = kt*x
            dT = 0.0
        else:
            Tn = T
            dT = kt*xd
        return [dd, -F/m, xd, -Tn/mt, dT, -Tn/m, Tn*r/I]
    s = [d, dd, x, xd, T, vc, w]
    started = False
    while True:
        k1 = deriv(s)
        k2 = deriv([s[i]+0.5*dt*k1[i] for i in range(7)])
        k3 = deriv([s[i]+0.5*dt*k2[i] for i in range(7)])
        k4 = deriv([s[i]+dt*k3[i] for i in range(7)])
        s = [s[i]+dt/6*(k1[i]+2*k2[i]+2*k3[i]+k4[i]) for i in range(7)]
        t += dt
        if s[0] > 0:
            started = True
        if started and s[0] <= 0:
            break
    vc, w = s[5], s[6]
    if DEBUG: print('t_end', t, s)
    return vc/vt, w, (vc - w*r)/vt

if __name__ == "__main__":
    ang = float(sys.argv[1]) if len(sys.argv) > 1 else 45
    V = float(sys.argv[2]) if len(sys.argv) > 2 else 10
    for law in ("incremental", "secant"):
        Rt, w, c = run(ang, V, law)
        print(f"angle={ang} law={law} R_t={Rt:.4f} omega={w:.4f} cp_ratio={c:.4f}")
