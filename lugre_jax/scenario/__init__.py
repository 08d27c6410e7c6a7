"""Scenarios: a JSON description of a joint, its controller, reference and solver, built into a
:class:`lugre_jax.System` (schema: :mod:`lugre_jax.scenario._build`). Sits above the simulator;
``lugre_jax.io`` holds the file formats below it."""

from ._build import (
    ADAPTIVE_SOLVERS as ADAPTIVE_SOLVERS,
    FIXED_SOLVERS as FIXED_SOLVERS,
    LANE_SOLVERS as LANE_SOLVERS,
    ScenarioError as ScenarioError,
    load_scenario as load_scenario,
    parse_friction as parse_friction,
    scenario_from_dict as scenario_from_dict,
)
