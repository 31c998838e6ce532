"""rocknroller: Routh's sphere and the rock'n'roller.

The public API, re-exported from the subpackages of :mod:`rocknroller.analysis`, from :mod:`rocknroller.numerics`
and :mod:`rocknroller.papers` (no physics lives here); the command line is :mod:`rocknroller.cli`.  Q_R comes before Q_J in every signature; where the paper orders them the other way (V_φ, V_ψ), they are
keyword-only::

    import rocknroller as rr

    body = rr.Body.paper(epsilon=1e-3)
    traj = rr.simulate(body, rr.EulerState.from_omega(0.95 * 3.141592653589793, 0, 0, (0, 1e-3, -1e-3)), 100.0)
    rr.region(traj.maxima.QR, traj.maxima.QJ, body)
"""

from rocknroller.analysis.criticality.lines import QJ_crit, QJ_crit_0, QJ_crit_pi, region, region_fractions
from rocknroller.analysis.criticality.reversals import reversal_analysis
from rocknroller.analysis.criticality.starts import CriticalStart, critical_start
from rocknroller.analysis.hierarchy.table import hierarchy_table
from rocknroller.analysis.criticality.theta_z import (cos_theta_z, delta_bound_coefficients, delta_of, theta_e, theta_z,
                                                      theta_z_expansion)
from rocknroller.analysis.model.body import Body, LoadedSphere
from rocknroller.analysis.model.diagnostics import azimuth_span
from rocknroller.analysis.model.equations import EulerState
from rocknroller.analysis.model.invariants import V_phi, V_psi
from rocknroller.analysis.routh.quadrature import Precession, precession, precession_from_turning_point
from rocknroller.analysis.routh.quadrature_mp import precession_mp
from rocknroller.analysis.routh.reduction import (F, NoMotionError, SteadyRollingError, effective_potential,
                                                  invariants_from_euler, state_from_turning_point)
from rocknroller.analysis.routh.turning_points import solve_turning_points, turning_points
from rocknroller.analysis.slow.atlas import Atlas, atlas_from_rest, atlas_of_rates
from rocknroller.analysis.slow.atlas_check import AtlasCheck, confirm_atlas
from rocknroller.analysis.slow.ensemble_statistics import (EnsembleComparison, EnsembleStatistics, StartBall,
                                                           compare_ensembles, map_ensemble, ode_ensemble)
from rocknroller.analysis.slow.map.maps import ExactMap, SlowMap
from rocknroller.analysis.slow.map.tables_at_once import (EnergyTables, build_energy_tables, build_release_tables,
                                                         load_energy_tables)
from rocknroller.analysis.slow.dynamics.pendulum import PendulumConstants, pendulum_constants, pendulum_prediction
from rocknroller.analysis.slow.dynamics.period_doubling import PeriodDoubling, period_doubling
from rocknroller.analysis.slow.dynamics.periodic_orbits import Branch, PeriodicOrbit, continue_orbit, periodic_orbit
from rocknroller.analysis.slow.prediction import SlowPrediction, predict_slow_motion
from rocknroller.numerics.ensembles.ensemble import Job, RunSummary, run_ensemble
from rocknroller.numerics.integrate import AccuracyError, AccuracyWarning, simulate
from rocknroller.numerics.provenance import __version__
from rocknroller.numerics.trajectory import Trajectory, TurningPointRun, TurningPoints
from rocknroller.papers.citation import cite

__all__ = [
    "__version__", "cite",
    # the body and the direct ODE
    "Body", "LoadedSphere", "hierarchy_table", "EulerState", "simulate", "Trajectory", "TurningPointRun", "TurningPoints", "AccuracyError",
    "AccuracyWarning", "direct_chaos_indicators", "DirectChaos",
    # many direct runs: in this process or on a dask.distributed cluster
    "Job", "RunSummary", "run_ensemble",
    # Routh's sphere: the reduction and the precession quadratures
    "F", "effective_potential", "turning_points", "solve_turning_points", "invariants_from_euler", "state_from_turning_point",
    "V_phi", "V_psi", "precession", "precession_from_turning_point", "precession_mp", "Precession",
    "NoMotionError", "SteadyRollingError",
    # criticality
    "QJ_crit_0", "QJ_crit_pi", "QJ_crit", "region", "region_fractions", "cos_theta_z", "theta_z", "theta_e", "delta_of",
    "delta_bound_coefficients", "theta_z_expansion", "critical_start", "CriticalStart", "reversal_analysis",
    "laurent_coefficients", "laurent_series", "laurent_function",
    # the slow motion of the rock'n'roller
    "predict_slow_motion", "SlowPrediction", "pendulum_constants", "pendulum_prediction", "PendulumConstants",
    "period_doubling", "PeriodDoubling", "periodic_orbit", "continue_orbit", "PeriodicOrbit", "Branch",
    "SlowMap", "ExactMap", "build_release_tables", "build_energy_tables", "load_energy_tables", "EnergyTables",
    "azimuth_span", "atlas_from_rest", "atlas_of_rates", "confirm_atlas", "Atlas", "AtlasCheck",
    "check_prediction", "PredictionCheck",
    # statistics where the slow motion is chaotic: map and ODE ensembles over a ball of starts, and their test
    "StartBall", "map_ensemble", "ode_ensemble", "compare_ensembles", "EnsembleStatistics", "EnsembleComparison",
    # figures
    "region_diagram", "DiagramData", "bifurcation_diagram", "slow_portrait", "write_portrait", "SlowPortrait",
    "period_doubling_line", "period_doubling_plot", "PeriodDoublingLine",
]

#: Loaded on first use (PEP 562), each from its module: the Laurent expansions are symbolic (sympy takes ~0.3 s to
#: import), the figures need matplotlib, the ODE check of a prediction runs the direct ODE (heyoka); the direct
#: motion's chaos indicators compile their own integrator (heyoka's variational equations) on first use.
_LAZY = {"direct_chaos_indicators": "rocknroller.numerics.variational",
         "DirectChaos": "rocknroller.numerics.variational",
         "laurent_coefficients": "rocknroller.analysis.criticality.laurent",
         "laurent_function": "rocknroller.analysis.criticality.laurent",
         "laurent_series": "rocknroller.analysis.criticality.laurent",
         "check_prediction": "rocknroller.papers.averaging_check",
         "PredictionCheck": "rocknroller.papers.averaging_check",
         "region_diagram": "rocknroller.papers.plotting",
         "DiagramData": "rocknroller.papers.plotting",
         "bifurcation_diagram": "rocknroller.papers.bifurcation",
         "period_doubling_line": "rocknroller.papers.bifurcation",
         "period_doubling_plot": "rocknroller.papers.bifurcation",
         "PeriodDoublingLine": "rocknroller.papers.bifurcation",
         "slow_portrait": "rocknroller.papers.portrait",
         "write_portrait": "rocknroller.papers.portrait_output",
         "SlowPortrait": "rocknroller.papers.portrait"}


def __getattr__(name: str) -> object:
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'rocknroller' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_LAZY))
