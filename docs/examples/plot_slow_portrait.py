"""
Phase portrait of the slow motion
=================================

Near pure rocking the averaged slow map is Chirikov's standard map p' = p + K sin Θ, Θ' = Θ + p' with K = εκ(θ0) and
p = ∇W(0)·Q (see the averaging page, "Closed forms").  At θ0 = 0.95π and ε = 5e-3, K = 2.1: a mixed phase space,
the islands of the stable rocking (Θ = π, ψ = π/2) and a chaotic layer along the separatrix through the unstable
rocking (Θ = 0).  The map's orbits from a small grid of starts are drawn in the (Θ, p) plane and in the (Q_R, Q_J)
plane over the critical lines; the releases from rest are the line p = 0, and the direct ODE from the release at
ψ0 = 0.1 (Θ = 0.2, near the unstable rocking) is overlaid.  ``rocknroller portrait`` draws the same from the command
line.  Each orbit is coloured by its MEGNO.
"""

# %%
import math

import rocknroller as rr
from rocknroller.papers.portrait import plot_portrait

body = rr.Body.paper(epsilon=5e-3)
portrait = rr.slow_portrait(body, 0.95 * math.pi, Theta=[0.1, 0.2, 1.0, 2.0, 2.6, 3.0], p=[-3.0, 0.0, 1.5, 3.0],
                            t_end=1000.0, ode_starts=[(0.2, 0.0)], progress=False)
print(f"K = eps kappa = {portrait.K:.3f}; {len(portrait.orbits)} orbits of the map, {len(portrait.ode)} direct run; "
      f"orbits that left the tables: {list(portrait.left)}")

# %%
# Each orbit is coloured by its MEGNO, from the map's tangent vector carried along it (colours clipped at 5; a
# regular orbit's MEGNO is about 2, a stable periodic one's 0, a chaotic one's grows without bound, above 3 chaotic):
# the separatrix's layer through Θ = 0 stands out.  ``plot_portrait(portrait, values)`` colours by other values.
chaotic = [k for k, c in enumerate(portrait.chaos) if c is not None and not c.regular]
print(f"chaotic orbits (MEGNO > 3): {chaotic}")
fig = plot_portrait(portrait)
