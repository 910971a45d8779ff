"""Placement seeds: deterministic start poses inside the start area, carried into the world and
the summary, and bad start areas named (pure, no ROS)."""

import math
import os

import pytest
import yaml

from conde_worlds import placement
from conde_worlds.challenge_world import challenge_world, start_poses, write_challenge
from conde_worlds.challenges import ChallengeError, load_challenges, parse_challenges
from conde_worlds.track_variation import track_dimensions

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CHALLENGES_FILE = os.path.join(PACKAGE_DIR, "challenges", "challenges.yaml")


@pytest.fixture(scope="module")
def challenges():
    return load_challenges(CHALLENGES_FILE)


def test_the_start_area_of_challenges_yaml(challenges):
    area = challenges.start_area
    assert area == placement.StartArea(along_m=(-0.10, 0.0), across_m=(-0.03, 0.03), yaw_deg=(-3.0, 3.0))


def test_seed_0_is_the_nominal_start_pose(challenges):
    world, _, _ = challenge_world(challenges, "D1", placement_seed=0)
    assert world["spawn"] == start_poses(challenges.challenges["D1"].start)
    assert placement.offset(0, challenges.start_area) == placement.Offset()


def test_every_seed_stays_inside_the_start_area_and_uses_all_of_it(challenges):
    area = challenges.start_area
    offsets = [placement.offset(seed, area) for seed in range(1, 501)]
    assert all(area.contains(o) for o in offsets)
    for axis in ("along_m", "across_m", "yaw_deg"):
        values = [getattr(o, axis) for o in offsets]
        lo, hi = getattr(area, axis)
        # spread over the area, not stuck at one value
        assert min(values) < lo + 0.1 * (hi - lo) and max(values) > hi - 0.1 * (hi - lo), axis
    assert len(set(offsets)) == len(offsets)


def test_a_seed_given_as_text_names_the_world_as_the_number(challenges):
    """roslaunch passes the seed as text: "0" is the nominal world (no _place0), " 3" is _place3."""
    nominal, _, _ = challenge_world(challenges, "D1")
    assert challenge_world(challenges, "D1", placement_seed="0")[0]["name"] == nominal["name"]
    assert challenge_world(challenges, "D1", placement_seed=" 3")[0]["name"] == nominal["name"] + "_place3"


def test_a_seed_always_gives_the_same_placement(challenges):
    a, _, _ = challenge_world(challenges, "P1", placement_seed=7)
    b, _, _ = challenge_world(challenges, "P1", placement_seed=7)
    c, _, _ = challenge_world(challenges, "P1", placement_seed=8)
    assert a["spawn"] == b["spawn"] != c["spawn"]
    assert a["name"].endswith("_place7")


@pytest.mark.parametrize("track_seed", [0, 3])
@pytest.mark.parametrize("challenge", ["D1", "B1"])
def test_the_placed_pose_is_the_offset_in_the_start_pose_frame(challenges, challenge, track_seed):
    nominal = start_poses(challenges.challenges[challenge].start, track_dimensions(track_seed))
    for seed in range(1, 21):
        world, _, _ = challenge_world(challenges, challenge, track_seed=track_seed, placement_seed=seed)
        expected = placement.offset(seed, challenges.start_area)
        for robot, pose in world["spawn"].items():
            got = placement.offset_of(nominal[robot], pose)
            assert got.along_m == pytest.approx(expected.along_m, abs=2e-4)
            assert got.across_m == pytest.approx(expected.across_m, abs=2e-4)
            assert got.yaw_deg == pytest.approx(expected.yaw_deg, abs=1e-3)
            assert challenges.start_area.contains(placement.Offset(round(got.along_m, 3), round(got.across_m, 3),
                                                                   round(got.yaw_deg, 2)))


def test_placed_moves_along_the_heading():
    pose = {"xyz": [2.0, -0.3, 0.0], "yaw": math.pi / 2}  # heading north
    moved = placement.placed(pose, placement.Offset(along_m=-0.1, across_m=0.02, yaw_deg=2.0))
    assert moved["xyz"] == pytest.approx([1.98, -0.4, 0.0])  # 0.1 m back (south), 0.02 m left (west)
    assert moved["yaw"] == pytest.approx(math.pi / 2 + math.radians(2.0), abs=1e-5)


def test_summary_and_output_folder_name_the_placement(tmp_path, monkeypatch, challenges):
    monkeypatch.setenv("ROS_HOME", str(tmp_path))
    paths = write_challenge("D1", placement_seed=4)
    assert paths["dir"] == os.path.join(str(tmp_path), "conde_challenges", "D1_v1_seed0_track0_place4")
    with open(paths["summary"]) as f:
        summary = yaml.safe_load(f)
    with open(paths["world"]) as f:
        world = yaml.safe_load(f)
    assert summary["placement_seed"] == 4
    assert summary["placement"] == placement.offset(4, challenges.start_area).summary()
    assert summary["start"] == world["spawn"]
    assert "--placement-seed 4" in open(paths["world"]).readline()


def good_data():
    with open(CHALLENGES_FILE) as f:
        return yaml.safe_load(f)


@pytest.mark.parametrize("edit, message", [
    (lambda p: p.update(along_m=[-0.1, 0.05]),
     "bad.yaml: placement.along_m: expected a number in [-0.15, 0], got 0.05"),
    (lambda p: p.update(across_m=[0.03, -0.03]), "bad.yaml: placement.across_m: lo 0.03 must not be above hi -0.03"),
    (lambda p: p.update(yaw_deg=3), "bad.yaml: placement.yaw_deg: expected [lo, hi], got 3"),
    (lambda p: p.update(z_m=[0, 0]),
     "bad.yaml: placement: unknown key 'z_m' (expected one of: along_m, across_m, yaw_deg)"),
])
def test_a_bad_start_area_is_named(edit, message):
    data = good_data()
    edit(data["placement"])
    with pytest.raises(ChallengeError) as e:
        parse_challenges(data, "/x/bad.yaml")
    assert str(e.value) == message


def test_a_bad_placement_seed_is_named(challenges):
    with pytest.raises(ChallengeError) as e:
        challenge_world(challenges, "D1", placement_seed="-2")
    assert str(e.value) == "placement seed: expected an integer >= 0, got '-2'"
