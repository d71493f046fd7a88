#!/usr/bin/env python3
"""Peer implementation of the clapper model in Python with SciPy.

Written the way a careful researcher would write it from the paper and
docs/model.md: equations (5) and (6) in mass-matrix form integrated by
scipy.integrate.solve_ivp (RK45, Dormand-Prince, the method of Matlab's
ode45 that the paper used) with event functions, and two contact models:

  impact   rigid impacts with restitution, restarting the integration after
           each impact; the clapper comes to rest when its next flight
           would be shorter than 1e-7 s, rides with the bell, and lifts off
           when the holding force changes sign (docs/model.md section 3);
  penalty  the paper's contact spring, stiffness k pressing in and R k
           springing back, one continuous integration.

It prints, for each stroke, the same quantities clapper does (first strike
angle in deg, clapper rate before it in rad/s, whether the style is
sustained), one JSON object a line, and the time the strokes took.

    python3 scipy_peer.py --chart 20 --model impact --rtol 1e-8
    python3 scipy_peer.py --bell lab --style right
"""
import argparse
import json
import math
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

G = 9.81


class Bell:
    def __init__(self, M, m, a, b, Ib, Ic, r, phimax):
        self.M, self.m, self.a, self.b = M, m, a, b
        self.Ib, self.Ic, self.r, self.phimax = Ib, Ic, r, phimax
        self.j0 = Ib + Ic + m * r * r
        self.mrb = m * r * b
        self.gb = (M * a + m * r) * G
        self.gc = m * b * G
        self.tb = 2 * math.pi * math.sqrt(Ib / (M * a) / G)


def lab():
    return Bell(45.8, 1.65, 0.24, 0.25, 4.1, 0.093, 0.10, math.radians(26))


def gsm_tenor():
    return Bell(1100.0, 34.0, 0.34, 0.80, 200.0, 33.0, 0.25, math.radians(32))


def chart_bell(x, y, tb=1.8, M=45.8, m=1.65, a=0.24, Ic=0.20, phimax=math.radians(26)):
    """The paper's construction of a bell at chart point (r/L_c, L_b/L_c)."""
    lb = G * tb * tb / (4 * math.pi ** 2)
    lc = lb / y
    return Bell(M, m, a, Ic / (m * lc), M * a * lb, Ic, x * lc, phimax)


def accel(bell, y, q=0.0):
    th, ph, thd, phd = y
    sp, cp = math.sin(ph), math.cos(ph)
    sth = math.sin(th + ph)
    w11 = bell.j0 + 2 * bell.mrb * cp
    w12 = bell.Ic + bell.mrb * cp
    f1 = bell.mrb * phd * (2 * thd + phd) * sp - bell.gb * math.sin(th) - bell.gc * sth
    f2 = q - bell.mrb * thd * thd * sp - bell.gc * sth
    det = w11 * bell.Ic - w12 * w12
    return (bell.Ic * f1 - w12 * f2) / det, (w11 * f2 - w12 * f1) / det, w11, w12, det


def resting(bell, y):
    """theta'' and the holding force Q_phi with the clapper held at rest."""
    th, ph, thd, _ = y
    sp, cp = math.sin(ph), math.cos(ph)
    sth = math.sin(th + ph)
    w11 = bell.j0 + 2 * bell.mrb * cp
    w12 = bell.Ic + bell.mrb * cp
    tdd = (-bell.gb * math.sin(th) - bell.gc * sth) / w11
    q = w12 * tdd + bell.mrb * thd * thd * sp + bell.gc * sth
    return tdd, q


def impact(bell, y, e):
    _, _, w11, w12, det = accel(bell, y)
    winv12, winv22 = -w12 / det, w11 / det
    p = -(1 + e) * y[3] / winv22
    return [y[0], y[1], y[2] + winv12 * p, -e * y[3]]


def event(fun, direction):
    fun.terminal = True
    fun.direction = direction
    return fun


def stroke(bell, theta0, R, style, model="impact", k=1e6, rtol=1e-8, max_steps_time=20.0):
    """One stroke from rest at +theta0; returns (first strike theta, phi', sustained, rhs calls)."""
    s0 = 1.0 if theta0 >= 0 else -1.0
    side = s0 if style == "right" else -s0
    y = [theta0, side * bell.phimax, 0.0, 0.0]
    t, t_end = 0.0, max_steps_time * bell.tb
    opts = dict(method="RK45", rtol=rtol, atol=rtol)
    nfev = 0
    first = None
    bottom_passed = False

    def over_top(t, y):
        return -s0 * y[0] - math.pi

    def bottom(t, y):
        return s0 * y[0]

    def turning(t, y):
        return s0 * y[2]

    def segment(rhs, t, t_end, y, extra, nfev):
        """Integrate to the first event: (over the top?, t, y, which event or None, rhs calls)."""
        evs = [event(over_top, 1), event(turning, 1) if bottom_passed else event(bottom, -1)] + extra
        sol = solve_ivp(rhs, (t, t_end), y, events=evs, **opts)
        nfev += sol.nfev
        if sol.status != 1:
            return False, t, y, None, nfev
        which = next(i for i, ev in enumerate(sol.t_events) if len(ev))
        return which == 0, sol.t_events[which][0], list(sol.y_events[which][0]), which, nfev

    if model == "penalty":
        # Loading with k, unloading with R k; the contact starts at |phi| = phimax.
        def rhs(t, y):
            pen = abs(y[1]) - bell.phimax
            q = 0.0
            if pen > 0:
                sgn = math.copysign(1.0, y[1])
                moving_in = sgn * y[3] > 0
                q = -sgn * (k if moving_in else R * k) * pen
            a = accel(bell, y, q)
            return [y[2], y[3], a[0], a[1]]

        # Start pressed into the spring by the resting force, as clapper does.
        _, q0 = resting(bell, y)
        if side * q0 < 0:
            y[1] -= q0 / (R * k)
        def hit(t, y):
            return -side * y[1] - bell.phimax  # reaches the far side's spring
        while True:
            extra = [event(hit, 1)] if first is None else []
            done, t, y, which, nfev = segment(rhs, t, t_end, y, extra, nfev)
            if done or which is None:
                return first, False, nfev
            if which == 1 and not bottom_passed:
                bottom_passed = True
                continue
            if which == 1:
                return first, first is not None and continues_as(y, None) == style, nfev
            first = (math.degrees(y[0]), y[3])

    e = math.sqrt(R)
    _, q0 = resting(bell, y)
    clapper = ("rest", side) if side * q0 < 0 else ("fly", None)
    struck = False
    while True:
        if clapper[0] == "fly":
            rhs = lambda t, y: [y[2], y[3], *accel(bell, y)[:2]]
            extra = [event(lambda t, y: y[1] - bell.phimax, 1), event(lambda t, y: -y[1] - bell.phimax, 1)]
        else:
            s = clapper[1]
            rhs = lambda t, y: [y[2], 0.0, resting(bell, y)[0], 0.0]
            extra = [event(lambda t, y, s=s: s * resting(bell, y)[1], 1)]
        done, t, y, which, nfev = segment(rhs, t, t_end, y, extra, nfev)
        if done or which is None:
            return first, False, nfev
        if which == 1 and not bottom_passed:
            bottom_passed = True
            continue
        if which == 1:
            rest = clapper[1] if clapper[0] == "rest" else None
            return first, first is not None and continues_as(y, rest) == style, nfev
        if clapper[0] == "rest":
            clapper = ("fly", None)
            continue
        s = 1.0 if which == 2 else -1.0
        if s != side and not struck:
            struck = True
            first = (math.degrees(y[0]), y[3])
        y[1] = s * bell.phimax
        bounced = impact(bell, y, e)
        toward = s * accel(bell, bounced)[1]
        away = -s * bounced[3]
        stuck = impact(bell, y, 0.0)
        if toward > 0 and 2 * away < 1e-7 * toward and s * resting(bell, stuck)[1] < 0:
            y, clapper = stuck, ("rest", s)
        else:
            y = bounced


def continues_as(y, rest_side):
    """The style the next stroke starts in: where the clapper is, relative to the bell."""
    side = rest_side if rest_side is not None else (1.0 if y[1] >= 0 else -1.0)
    return "right" if side == (1.0 if y[0] >= 0 else -1.0) else "wrong"


def axis(a, b, n):
    return [0.5 * (a + b)] if n == 1 else [a + (b - a) * i / (n - 1) for i in range(n)]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--chart", type=int, help="N x N chart over r/L_c -0.3..0.7, L_b/L_c 0.5..2.5, both styles")
    ap.add_argument("--bell", choices=["lab", "gsm-tenor"])
    ap.add_argument("--style", choices=["right", "wrong"], default="right")
    ap.add_argument("--model", choices=["impact", "penalty"], default="impact")
    ap.add_argument("--stiffness", type=float, default=1e6)
    ap.add_argument("--theta0", type=float, default=171.0)
    ap.add_argument("--restitution", type=float, default=0.2)
    ap.add_argument("--rtol", type=float, default=1e-8)
    a = ap.parse_args()
    jobs = []
    if a.chart:
        for y in axis(0.5, 2.5, a.chart):
            for x in axis(-0.3, 0.7, a.chart):
                for st in ("right", "wrong"):
                    jobs.append(((x, y), chart_bell(x, y), st))
    else:
        jobs.append((a.bell or "lab", lab() if a.bell != "gsm-tenor" else gsm_tenor(), a.style))
    start = time.perf_counter()
    for where, bell, st in jobs:
        first, sustained, nfev = stroke(bell, math.radians(a.theta0), a.restitution, st, a.model, a.stiffness, a.rtol)
        print(json.dumps({
            "point": where, "style": st, "sustained": sustained, "rhs_evals": nfev,
            "strike_theta_deg": first[0] if first else None,
            "strike_phidot_rad_s": first[1] if first else None,
        }))
    secs = time.perf_counter() - start
    print(json.dumps({"strokes": len(jobs), "seconds": secs, "seconds_per_stroke": secs / len(jobs)}))


if __name__ == "__main__":
    sys.exit(main())
