"""
Chaplygin's top: the direct ODE, its turning points and its chaos indicators
============================================================================

A loaded sphere whose mass centre lies off every principal axis (``rr.Body.chaplygin_top``): the paper's quantities
Q_J and Q_R do not apply (they refuse with a ValueError), but the direct ODE, its turning points of the tilt θ of
the third axis, the ensembles and the chaos indicators take it as they take the paper's body.  The azimuth φ at the
θ-maxima shows the direction of precession over a long run; MEGNO tells whether the motion is regular.
"""

# %%
import math

import numpy as np
from matplotlib.figure import Figure

import rocknroller as rr

top = rr.Body.chaplygin_top(0.35, 0.37, 0.4, offset=(0.03, -0.02, -0.05))
start = rr.EulerState(0.9 * math.pi, psi=0.3)
run = rr.simulate(top, start, 2000.0, samples=False, progress=False)
chaos = rr.direct_chaos_indicators(top, start, 2000.0)
print(f"{len(run.maxima)} θ-maxima, energy error {run.energy_rel_error:.1e}")
print(f"MEGNO {chaos.indicators.megno:.3g}: {'regular' if chaos.indicators.regular else 'chaotic'}")
try:
    run.maxima.QJ
except ValueError as err:
    print(str(err)[:90], "...")

fig = Figure(figsize=(9, 3.6))
ax1, ax2 = fig.subplots(1, 2)
ax1.plot(run.maxima.t, run.maxima.phi / math.pi, ".", ms=2, color="k")
ax1.set_xlabel("t")
ax1.set_ylabel(r"$\phi$ at the $\theta$-maxima ($\pi$ rad)")
ax2.plot(run.maxima.t, np.degrees(run.maxima.theta), ".", ms=2, color="tab:blue")
ax2.set_xlabel("t")
ax2.set_ylabel(r"$\theta$ at the maxima (degrees)")
fig.suptitle("Chaplygin's top, c = (0.03, −0.02, −0.05), released at θ0 = 0.9π", fontsize=9)
fig.tight_layout()
fig
