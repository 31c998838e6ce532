"""
The critical lines with an orbit that crosses them
==================================================

A start is placed on the critical line Q_J = Q_J,π^crit by computation (paper fig. 8: θ0 = 0.95π, ψ0 = π/4, ψ̇0 = 0.002), the
asymmetric body (ε = 1e-3) is integrated for 200 time units, and its (Q_R(t), Q_J(t)) orbit is drawn over the four
regions by ``rr.region_diagram``, with the θ-maxima in red and the θ-minima in blue; beside it, V_φ(θ) at one point
of each region (``rr.region_diagram(body)`` alone draws the regions of paper fig. 4).
"""

# %%
import math

import rocknroller as rr

body = rr.Body.paper(epsilon=1e-3)
theta0, psi0 = 0.95 * math.pi, math.pi / 4
start = rr.critical_start(body, theta0, psi0, "pi", psi_dot0=0.002)
print(f"on the line: Q_R = {float(start.QR):.6g}, Q_J = {float(start.QJ):.6g}, phi_dot0 = {float(start.phi_dot0):.6g}")
traj = rr.simulate(body, start.state(), t_end=200.0)
fig, data = rr.region_diagram(body, traj=traj)  # a matplotlib Figure: fig.savefig("regions.png") keeps it whole

# %%
# The crossings of the critical lines
# -----------------------------------
# The visible angle reverses where Q_J − Q_J,π^crit changes sign between consecutive θ-maxima, the full angle where
# Q_J − Q_J,0^crit changes sign between consecutive θ-minima (paper §Recession).
analysis = rr.reversal_analysis(traj)
print(f"visible-angle reversals: {analysis.count('pi')}, full-angle reversals: {analysis.count('0')}")
for crossing in analysis.crossings[:8]:
    print(crossing)
