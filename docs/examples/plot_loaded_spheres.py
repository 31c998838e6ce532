"""
The four loaded spheres and their integrals
===========================================

The paper's fig. 1 family, one representative each (``rocknroller.analysis.hierarchy.members``): Chaplygin's ball
(mass centre at the centre), Routh's sphere (on the axis of a body of revolution), the rock'n'roller (on a principal
axis, I1 ≠ I2) and Chaplygin's top (off every principal axis).  Each is released with the same tilt and spin and
integrated by the same general equations; beside each contact track, the relative change of Jellett's M·r and of
Chaplygin's M·M along the run shows which is an integral of which member (sympy proves the same:
``rocknroller hierarchy``).
"""

# %%
import numpy as np
from matplotlib.figure import Figure

import rocknroller as rr
from rocknroller.analysis.hierarchy.members import MEMBER_BODIES, member_start
from rocknroller.analysis.model.invariants import momentum_along_offset_line, momentum_squared

fig = Figure(figsize=(10, 7.5))
axes = fig.subplots(4, 2)
for (kind, body), (track, change) in zip(MEMBER_BODIES.items(), axes):
    run = rr.simulate(body, member_start(), 60.0, progress=False)
    track.plot(run.X, run.Y, color="k", lw=0.6)
    track.set_aspect("equal", adjustable="datalim")
    track.set_ylabel("Y", fontsize=8)
    track.set_title(f"{kind}: c = {body.offset}, I = ({body.I1}, {body.I2}, {body.I3})", fontsize=8)
    for f, label in ((momentum_along_offset_line, "Jellett M·r"), (momentum_squared, "Chaplygin M·M")):
        q = f(body, run.gamma, run.omega)
        change.semilogy(run.t, np.abs(q - q[0]) / np.max(np.abs(q)) + 1e-17, lw=0.7, label=label)
    change.set_ylim(1e-17, 1e5)
    change.set_ylabel("|Q(t) − Q(0)| / |Q|", fontsize=8)
    change.legend(fontsize=7, loc="upper left", ncols=2)
    print(f"{kind:16} energy error {run.energy_rel_error:.1e}")
axes[-1, 0].set_xlabel("X")
axes[-1, 1].set_xlabel("t")
fig.tight_layout()
fig
