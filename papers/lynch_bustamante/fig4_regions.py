"""Paper fig. 4: the four critical regions of the (Q_R, Q_J) plane with V_φ(θ) in each (paper body, I1 = I2)."""

from __future__ import annotations

from pathlib import Path

from rocknroller.analysis.model.body import Body
from rocknroller.papers.output import Reproduction, save_figure, write_csv
from rocknroller.papers.plotting import region_diagram

NAME = "fig4"


def run(out: Path) -> Reproduction:
    """Paper fig. 4: writes ``fig4_regions.png`` and ``.pdf`` (Regions I–IV, with V_φ(θ) at a representative
    point of each; paper body, I1 = I2) and ``fig4_critical_lines.csv`` (Q_R, Q_J,0^crit, Q_J,π^crit); numbers:
    the representative (Q_R, Q_J) of each region and the slopes Q_J/Q_R of the two critical lines."""
    body = Body.paper()
    fig, data = region_diagram(body, title="Paper fig. 4: critical Jellett lines and regions I-IV")
    paths = save_figure(fig, out, "fig4_regions")
    paths.append(write_csv(out / "fig4_critical_lines.csv", {
        "Q_R": data.QR_line, "Q_J_crit_0": data.QJ0_line, "Q_J_crit_pi": data.QJpi_line},
        ["paper fig. 4: critical Jellett lines (paper eqs. QJcrit_0, QJcrit_pi)", f"body: {body.describe()}"]))
    numbers: dict[str, float | str] = {f"representative {k}": f"Q_R={v[0]:.4g}, Q_J={v[1]:.4g}"
                                       for k, v in data.representatives.items()}
    numbers["slope of Q_J,0^crit"] = float(data.QJ0_line[-1] / data.QR_line[-1])
    numbers["slope of Q_J,pi^crit"] = float(data.QJpi_line[-1] / data.QR_line[-1])
    caption = ("The critical lines Q_J,0^crit (full-angle reversal) and Q_J,π^crit (visible-angle reversal) divide the "
               "(Q_R, Q_J) plane into Regions I–IV; each panel shows V_φ(θ) at a representative point.")
    return Reproduction(NAME, caption, paths, numbers)
