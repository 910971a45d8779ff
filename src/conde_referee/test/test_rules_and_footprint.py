"""Bad input with exact messages: the rules file and a robot description without collision
geometry; the placeholder rules file's values; the footprint of the project's robots."""
import os
import subprocess

import pytest
import yaml

from conde_referee.footprint import FootprintError, footprint_from_urdf
from conde_referee.rules import RulesError, default_path, load_rules


def test_placeholder_rules_have_the_third_party_referee_values():
    rules = load_rules()
    assert "placeholder" in rules.name
    p, s = rules.penalties, rules.scoring
    assert (p["line_touch"], p["leave_road"], p["stop_not_respected"], p["wrong_branch"], p["parking_line_touch"]) == (
        10, 20, 60, 25, 10)
    assert (s["laps"], s["points_per_half_lap"], s["reference_half_lap_s"], s["parking_points"],
            s["parking_stay_s"], s["repeat_debounce_s"]) == (2, 50, 35, 60, 5, 2)


def _write(tmp_path, change):
    with open(default_path()) as f:
        data = yaml.safe_load(f)
    change(data)
    path = tmp_path / "rules.yaml"
    path.write_text(yaml.safe_dump(data))
    return str(path)


@pytest.mark.parametrize("change, message", [
    (lambda d: d["penalties"].update(line_touch="ten"),
     "rules.yaml: penalties.line_touch: expected a number >= 0, got 'ten'"),
    (lambda d: d["penalties"].update(line_tuoch=10),
     "rules.yaml: penalties: unknown key 'line_tuoch' (expected one of: false_start, line_touch, leave_road, "
     "wrong_direction, stop_not_respected, stopped_outside_zone, wrong_branch, collision, parking_line_touch, "
     "sign_wrong)"),
    (lambda d: d["scoring"].pop("laps"), "rules.yaml: scoring: missing key 'laps'"),
    (lambda d: d["scoring"].update(laps=1.5), "rules.yaml: scoring.laps: expected a whole number >= 1, got 1.5"),
    (lambda d: d["judging"].update(standstill_s=-1),
     "rules.yaml: judging.standstill_s: expected a number >= 0, got -1"),
    (lambda d: d.update(format="v2"), "rules.yaml: format: expected 'conde_referee_rules/1', got 'v2'"),
    (lambda d: d.update(bonus=3), "rules.yaml: top level: unknown key 'bonus' (expected one of: format, name, "
     "penalties, scoring, judging)"),
])
def test_malformed_rules_file(tmp_path, change, message):
    with pytest.raises(RulesError) as e:
        load_rules(_write(tmp_path, change))
    assert str(e.value) == message


def test_rules_file_that_is_not_yaml(tmp_path):
    path = tmp_path / "rules.yaml"
    path.write_text("penalties: [")
    with pytest.raises(RulesError) as e:
        load_rules(str(path))
    assert str(e.value).startswith("rules.yaml:1: not valid YAML: ")  # the file and the line


NO_COLLISION = """<robot name="ghost"><link name="base_link">
  <visual><geometry><box size="1 1 1"/></geometry></visual></link></robot>"""


def test_robot_without_collision_geometry():
    with pytest.raises(FootprintError) as e:
        footprint_from_urdf(NO_COLLISION)
    assert str(e.value) == ("robot_description: robot 'ghost' has no collision geometry (a <collision> with a box, "
                            "cylinder or sphere): the referee needs it for the robot's footprint")


def test_footprint_follows_the_joints():
    urdf = """<robot name="r"><link name="base_footprint"/>
      <link name="body"><collision><origin xyz="0.1 0 0.1"/>
        <geometry><box size="0.4 0.2 0.2"/></geometry></collision></link>
      <joint name="j" type="fixed"><parent link="base_footprint"/><child link="body"/>
        <origin xyz="-0.2 0 0.05"/></joint>
    </robot>"""
    fp = footprint_from_urdf(urdf)
    assert [round(v, 6) for v in (fp.x_min_m, fp.x_max_m, fp.y_min_m, fp.y_max_m, fp.z_max_m)] == [
        -0.3, 0.1, -0.1, 0.1, 0.25]


def test_footprint_of_conde():
    xacro = os.path.join(subprocess.run(["rospack", "find", "conde_description"], capture_output=True, text=True,
                                        check=True).stdout.strip(), "robots", "conde.urdf.xacro")
    fp = footprint_from_urdf(subprocess.run(["xacro", xacro], capture_output=True, text=True, check=True).stdout)
    # The body reaches back from the drive axle (base_footprint) and 5 cm ahead of it.
    assert round(fp.x_max_m, 3) == 0.05 and fp.x_min_m < -0.4 and round(fp.y_max_m, 4) == 0.1825
