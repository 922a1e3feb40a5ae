"""Isaac 5's Franka examples select the asset's USD variants on the prim add_reference_to_stage
returns; here the selection is kept and the bundled model runs as it is (it raised AttributeError)."""

from __future__ import annotations

import numpy as np
import pytest

from manip.errors import InvalidInputError
from manip.sim import Articulation, SimulationContext, add_reference_to_stage, get_assets_root_path


def test_isaac5s_variant_selection_is_kept_and_the_franka_runs():
    robot = add_reference_to_stage(get_assets_root_path() + "/Isaac/Robots/FrankaRobotics/FrankaPanda/franka.usd",
                                   "/Franka")
    assert robot.GetVariantSet("Gripper").SetVariantSelection("AlternateFinger")
    robot.GetVariantSet("Mesh").SetVariantSelection("Quality")
    assert robot.GetVariantSet("Gripper").GetVariantSelection() == "AlternateFinger"
    assert robot.GetVariantSet("Physics").GetVariantSelection() == ""
    sim = SimulationContext()
    sim.initialize_physics()
    art = Articulation("/Franka")
    art.initialize()
    dof = art.get_dof_index("panda_joint2")
    sim.play()
    for _ in range(60):
        art.set_joint_positions([-1.5], joint_indices=[dof])
        sim.step(render=False)
    assert art.get_joint_positions(joint_indices=[dof])[0] == pytest.approx(-1.5, abs=0.02)  # set, then one step
    assert np.all(np.isfinite(art.get_joint_positions()))
    with pytest.raises(InvalidInputError, match="variant name"):
        robot.GetVariantSet("Gripper").SetVariantSelection("")
