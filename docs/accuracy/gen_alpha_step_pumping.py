#!/usr/bin/env python3
"""Energy pumped by generalized-alpha steps that vary with the motion, on a pendulum (q'' = -sin q).

A model of the method of `integrate/generalized_alpha` (Chung and Hulbert's parameters from rho_inf, the
shift of a_n to a new step size as in `predict`), without constraints. The step follows a profile
h = h0 (1 + amp sin(w t)) correlated with the swing (w twice the swing's frequency), and the energy drift is
the mean energy error over the last tenth of the run minus that over the first tenth. With the state moved
between the two step sizes' O(h^2) offsets at each change, y += (h^2 - h_p^2) * kappa * y'' (the trapezoidal
rule conserves E + h^2/12 H''(f, f), so kappa = 1/12), the drift is gone; docs/accuracy.md, *Generalized-alpha's
steps lagging the motion*. Usage: python3 gen_alpha_step_pumping.py
"""
import math


def drift(rho, kappa_q, kappa_v, h0=0.02, amp=0.3, t_end=200.0, w=2.0):
    am, af = (2 * rho - 1) / (rho + 1), rho / (rho + 1)
    g = 0.5 + af - am
    b = 0.25 * (g + 0.5) ** 2
    energy = lambda q, v: 0.5 * v * v + (1 - math.cos(q))
    q, v = 1.0, 0.0
    vd = -math.sin(q)
    a_tilde, vd_old, t, h_last = vd, vd, 0.0, 0.0
    e0, errors = energy(q, v), []
    while t < t_end:
        h = h0 * (1 + amp * math.sin(w * t))
        if h_last > 0:
            vdd, dh2 = (vd - vd_old) / h_last, h * h - h_last * h_last
            a_start = a_tilde + (am - af) * (h - h_last) * vdd
            q_s, v_s = q + kappa_q * dh2 * vd, v + kappa_v * dh2 * vdd
        else:
            a_start, q_s, v_s = a_tilde, q, v
        x = vd
        for _ in range(50):
            a_new = ((1 - af) * x + af * vd - am * a_start) / (1 - am)
            q_new = q_s + h * v_s + h * h * ((0.5 - b) * a_start + b * a_new)
            residual = x + math.sin(q_new)
            dx = -residual / (1 + math.cos(q_new) * h * h * b * (1 - af) / (1 - am))
            x += dx
            if abs(dx) < 1e-15:
                break
        a_new = ((1 - af) * x + af * vd - am * a_start) / (1 - am)
        q_new = q_s + h * v_s + h * h * ((0.5 - b) * a_start + b * a_new)
        v_new = v_s + h * ((1 - g) * a_start + g * a_new)
        vd_old, vd, a_tilde, q, v, h_last, t = vd, x, a_new, q_new, v_new, h, t + h
        errors.append(energy(q, v) - e0)
    n = len(errors) // 10
    return sum(errors[-n:]) / n - sum(errors[:n]) / n


if __name__ == "__main__":
    print("rho_inf  drift, steps as they come  moved by 1/12 (q and v)")
    for rho in (1.0, 0.8, 0.5):
        print("%6.1f   %24.2e  %22.2e" % (rho, drift(rho, 0, 0), drift(rho, 1 / 12, 1 / 12)))
