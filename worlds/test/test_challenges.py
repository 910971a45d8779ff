"""The challenge generator: descriptions, layouts, dimensions, seeds and bad input (pure, no ROS)."""

import math
import os

import cv2
import numpy as np
import pytest
import yaml

from conde_worlds import challenge_objects as co
from conde_worlds import track_geometry as tg
from conde_worlds import traffic_signs
from conde_worlds.challenge_world import challenge_world, layout, write_challenge
from conde_worlds.challenges import ChallengeError, load_challenges, parse_challenges

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CHALLENGES_FILE = os.path.join(PACKAGE_DIR, "challenges", "challenges.yaml")
ALL = [(c, v) for c, ch in load_challenges(CHALLENGES_FILE).challenges.items() for v in ch.variants]
SEEDS = range(1, 201)


@pytest.fixture(scope="module")
def challenges():
    return load_challenges(CHALLENGES_FILE)


@pytest.fixture(scope="module")
def track():
    return tg.build_track()


def objects(challenges, challenge, variant=None, seed=0, prefix=""):
    world, _, _ = challenge_world(challenges, challenge, variant, seed)
    return [o for o in world["objects"] if o["name"].startswith(prefix)]


def radius(loop, x, y):
    cx, cy = co.loop_centre(loop)
    return math.hypot(x - cx, y - cy)


def test_every_challenge_of_the_rules_is_described(challenges):
    assert sorted(challenges.challenges) == ["B1", "B2", "D1", "D2", "D3", "D4", "P1", "P2", "V1"]
    assert list(challenges.challenges["D3"].variants) == ["v1", "v2"]
    assert list(challenges.challenges["B2"].variants) == ["v1", "v2"]


@pytest.mark.parametrize("challenge,variant", ALL)
def test_every_world_keeps_the_track_and_panels_and_starts_each_robot(challenges, track, challenge, variant):
    world, _, _ = challenge_world(challenges, challenge, variant, 0)
    assert world["format"] == "conde_world/1"
    assert world["name"] == "challenge_%s_%s_seed0" % (challenge, variant)
    assert world["ground"]["texture"] == "package://conde_worlds/textures/competition_track.png"
    names = [o["name"] for o in world["objects"]]
    assert names[:2] == ["monitor_lcd1", "monitor_lcd2"] and len(set(names)) == len(names)
    assert set(world["spawn"]) == {"conde", "major_alvega"}
    for pose in world["spawn"].values():
        assert track.on_road([pose["xyz"][:2]])[0]


def test_d1_d2_p1_b1_have_no_objects_beyond_the_panels(challenges):
    for c in ("D1", "D2", "P1", "B1"):
        assert [o["name"] for o in objects(challenges, c)] == ["monitor_lcd1", "monitor_lcd2"]


def test_d2_schedule_gives_every_order(challenges):
    signals = {s["signal"] for s in challenges.challenges["D2"].schedule}
    assert {"stop", "left", "right", "forward", "end_of_trial", "parking"} <= signals


def test_obstacle_boxes_have_the_rules_size_and_sit_on_the_floor(challenges):
    boxes = objects(challenges, "D3", "v1", prefix="obstacle_")
    assert len(boxes) == 2
    for b in boxes:
        assert b["size_m"] == [0.6, 0.6, 0.2] and b["color_rgb"] == [0.0, 1.0, 0.0]
        assert b["pose"]["xyz"][2] == pytest.approx(0.1) and b["mass_kg"] == 10.0


def lane_side_of_corners(box):
    """+1 / -1 for each corner outside / inside the lane divider of the box's loop."""
    loop = "north" if box["pose"]["xyz"][1] > 0 else "south"
    return [radius(loop, x, y) - co.DIVIDER_R for x, y in co.box_corners(box)], loop


def assert_one_lane_blocked_other_free(box):
    half_dash = tg.DASHED_WIDTH / 2.0
    offsets, loop = lane_side_of_corners(box)
    # Every corner on the same side of the divider (off its paint) and inside the boundary lines.
    assert all(d > half_dash for d in offsets) or all(d < -half_dash for d in offsets), offsets
    r = [radius(loop, x, y) for x, y in co.box_corners(box)]
    assert min(r) > co.ISLAND_LINE_R + tg.SOLID_WIDTH / 2 and max(r) < co.OUTER_LINE_R - tg.SOLID_WIDTH / 2
    # The box blocks its lane: it covers the lane centre.
    cx, cy = box["pose"]["xyz"][:2]
    lane_r = radius(loop, cx, cy)
    assert min(abs(lane_r - co.LANE_R["inner"]), abs(lane_r - co.LANE_R["outer"])) < 1e-3


@pytest.mark.parametrize("challenge,variant", [("D3", "v1"), ("D3", "v2"), ("D4", "v1"), ("D4", "v2")])
def test_variant_boxes_block_one_lane_per_loop(challenges, challenge, variant):
    boxes = objects(challenges, challenge, variant, prefix="obstacle_")
    assert sorted("north" if b["pose"]["xyz"][1] > 0 else "south" for b in boxes) == ["north", "south"]
    for b in boxes:
        assert_one_lane_blocked_other_free(b)


def test_random_boxes_leave_the_other_lane_free_for_many_seeds(challenges):
    lanes = set()
    for seed in SEEDS:
        for b in objects(challenges, "D3", "v1", seed, prefix="obstacle_"):
            assert_one_lane_blocked_other_free(b)
        _, _, _, features = layout(challenges, "D3", "v1", seed)
        lanes |= {(o["loop"], o["lane"]) for o in features["obstacles"]}
    assert len(lanes) == 4  # both lanes of both loops occur


def test_random_d4_boxes_stay_out_of_the_working_zone_and_the_tunnel(challenges):
    for seed in SEEDS:
        _, _, _, f = layout(challenges, "D4", "v1", seed)
        for ob in f["obstacles"]:
            for zone in (f["working_zone"], f["tunnel"]):
                if zone["loop"] == ob["loop"]:
                    assert not zone["from_deg"] - 15 <= ob["angle_deg"] <= zone["to_deg"] + 15


@pytest.mark.parametrize("variant", ["v1", "v2"])
def test_d4_variant_boxes_stay_out_of_the_working_zone_and_the_tunnel(challenges, variant):
    f = challenges.challenges["D4"].variants[variant]
    for ob in f["obstacles"]:
        for zone in (f["working_zone"], f["tunnel"]):
            if zone["loop"] == ob["loop"]:
                assert not zone["from_deg"] - 15 <= ob["angle_deg"] <= zone["to_deg"] + 15


def test_layout_is_a_function_of_the_seed(challenges):
    assert objects(challenges, "D3", "v1", 7) == objects(challenges, "D3", "v1", 7)
    assert objects(challenges, "D3", "v1", 7) != objects(challenges, "D3", "v1", 8)
    assert objects(challenges, "D3", "v1", 0) != objects(challenges, "D3", "v2", 0)


def test_cones_have_the_rules_size_and_close_the_lane_from_edge_to_divider(challenges):
    cones = objects(challenges, "D4", "v1", prefix="cone_")
    assert len(cones) >= 9
    r = [radius("north", *c["pose"]["xyz"][:2]) for c in cones]
    for c in cones:
        assert c["shape"] == "cone" and 2 * c["radius_m"] == pytest.approx(0.15) and c["length_m"] == 0.23
    # The taper starts at the outer line and reaches the divider; no cone base on the open lane.
    assert r[0] > co.OUTER_LINE_R - 0.2 and r[-1] > co.OUTER_LINE_R - 0.2
    assert min(r) - co.CONE_BASE_RADIUS_M > co.DIVIDER_R + tg.DASHED_WIDTH / 2 - 1e-9
    assert min(r) < co.DIVIDER_R + 0.2


def test_tunnel_is_roofed_and_its_walls_stand_off_the_road(challenges):
    parts = objects(challenges, "D4", "v1", prefix="tunnel_")
    walls = [p for p in parts if p["name"].startswith("tunnel_wall_")]
    roofs = [p for p in parts if p["name"].startswith("tunnel_roof_")]
    assert roofs and len(walls) == 2 * len(roofs)
    for w in walls:
        r = [radius("south", x, y) for x, y in co.box_corners(w)]
        if "_inner_" in w["name"]:  # inside the island, clear of its painted line
            assert max(r) < co.ISLAND_LINE_R - tg.SOLID_WIDTH / 2
        else:  # outside the outer line
            assert min(r) > co.OUTER_LINE_R + tg.SOLID_WIDTH / 2
        assert w["size_m"][2] == co.TUNNEL_HEIGHT_M
    for roof in roofs:
        bottom = roof["pose"]["xyz"][2] - roof["size_m"][2] / 2
        assert bottom == pytest.approx(co.TUNNEL_HEIGHT_M)


def _inside(polygon, x, y):
    inside = False
    for (xi, yi), (xj, yj) in zip(polygon, polygon[-1:] + polygon[:-1]):
        if (yi > y) != (yj > y) and x < xi + (y - yi) * (xj - xi) / (yj - yi):
            inside = not inside
    return inside


def test_tunnel_has_a_darker_light_region_between_its_walls(challenges):
    world, _, _ = challenge_world(challenges, "D4", "v1", 0)
    [region] = world["light_regions"]
    assert region["name"] == "tunnel_south" and region["light"] == co.TUNNEL_LIGHT < 1.0
    assert region["z_range_m"] == [-0.01, co.TUNNEL_HEIGHT_M]
    polygon = region["polygon_xy_m"]
    # The lanes' centres under the roof (110..200 deg) are inside; before and after it, outside.
    for lane in ("inner", "outer"):
        for angle, expected in ((112, True), (155, True), (198, True), (100, False), (210, False)):
            x, y, _ = co.loop_point("south", angle, co.LANE_R[lane])
            assert _inside(polygon, x, y) == expected, (lane, angle)
    # Outside the walls, and the north loop, stay lit.
    x, y, _ = co.loop_point("south", 155, co.OUTER_LINE_R + 0.4)
    assert not _inside(polygon, x, y)
    x, y, _ = co.loop_point("north", 155, co.LANE_R["inner"])
    assert not _inside(polygon, x, y)
    for challenge in ("D1", "D3", "V1"):
        assert "light_regions" not in challenge_world(challenges, challenge, None, 0)[0]


def test_parallel_boxes_are_in_the_bay_with_the_gap(challenges):
    boxes = objects(challenges, "P2", prefix="parked_box_")
    (x0, x1), (y0, y1) = co.parallel_bay()
    ys = sorted(b["pose"]["xyz"][1] for b in boxes)
    assert ys[1] - ys[0] - 0.6 == pytest.approx(1.2)
    for b in boxes:
        for x, y in co.box_corners(b):
            assert x0 < x < x1 and y0 < y < y1


@pytest.mark.parametrize("variant,bay", [("v1", "north"), ("v2", "south")])
def test_bay_box_fills_one_bay(challenges, track, variant, bay):
    (box,) = objects(challenges, "B2", variant, prefix="parked_box_")
    assert box["name"] == "parked_box_" + bay
    assert all(track.in_bay([c], bay)[0] for c in co.box_corners(box))
    other = "south" if bay == "north" else "north"
    assert not any(track.in_bay([c], other)[0] for c in co.box_corners(box))


def test_bay_seed_picks_both_bays(challenges):
    bays = {objects(challenges, "B2", "v1", seed, prefix="parked_box_")[0]["name"] for seed in range(1, 30)}
    assert bays == {"parked_box_north", "parked_box_south"}


def signs(challenges, seed):
    return objects(challenges, "V1", None, seed, prefix="sign_")


def test_twelve_signs_of_the_rules_size_one_metre_high(challenges, track):
    s = signs(challenges, 0)
    assert len(s) == 12
    assert sorted(o["name"].split("_", 2)[2] for o in s) == sorted(traffic_signs.SIGNS)
    for o in s:
        assert o["size_m"][:2] == [0.305, 0.305] and o["pose"]["xyz"][2] == 1.0
        assert o["texture"] == "textures/sign_%s.png" % o["name"].split("_", 2)[2]
        assert not track.on_road([o["pose"]["xyz"][:2]])[0]


def test_signs_are_shuffled_by_the_seed_and_all_twelve_stay(challenges):
    orders = set()
    for seed in range(0, 20):
        s = signs(challenges, seed)
        names = tuple(o["name"].split("_", 2)[2] for o in s)
        assert sorted(names) == sorted(traffic_signs.SIGNS)
        assert [o["pose"]["xyz"][:2] for o in s] == [[x, y] for x, y, _ in co.SIGN_POSES]
        orders.add(names)
    assert len(orders) == 20
    assert [o["name"] for o in signs(challenges, 3)] == [o["name"] for o in signs(challenges, 3)]


def test_sign_pictograms_differ_and_use_their_family_colours():
    images = {s: traffic_signs.draw_sign(s) for s in traffic_signs.SIGNS}
    for s, img in images.items():
        assert img.shape == (traffic_signs.SIZE_PX, traffic_signs.SIZE_PX, 3) and img.dtype == np.uint8
        centre = img[40:90, 40:90].reshape(-1, 3)
        colour = traffic_signs.RED if traffic_signs.FAMILY[s] == "danger" else traffic_signs.BLUE
        whole = img.reshape(-1, 3)
        assert np.mean(np.all(np.abs(whole.astype(int) - colour) < 30, axis=1)) > 0.1, s
        assert len(np.unique(centre, axis=0)) > 2, s  # a pictogram, not a plain plate
    names = list(images)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            assert np.mean(np.abs(images[a].astype(int) - images[b].astype(int))) > 2.0, (a, b)


def test_write_challenge_writes_world_textures_schedule_and_summary(tmp_path):
    paths = write_challenge("V1", "v1", 4, str(tmp_path))
    world = yaml.safe_load(open(paths["world"]))
    for o in world["objects"]:
        if "texture" in o:
            img = cv2.imread(os.path.join(str(tmp_path), o["texture"]))
            assert img is not None and img.shape[:2] == (128, 128)
    schedule = yaml.safe_load(open(paths["schedule"]))
    assert schedule["steps"][0] == {"at_s": 0.0, "signal": "stop"}
    summary = yaml.safe_load(open(paths["summary"]))
    assert summary["challenge"] == "V1" and summary["seed"] == 4 and summary["time_limit_s"] == 300
    assert "&id" not in open(paths["world"]).read()  # no YAML aliases


def test_the_panel_controller_accepts_every_schedule(challenges):
    from conde_signalling_panel_control.schedule import parse_schedule  # the devel space's
    for name, ch in challenges.challenges.items():
        parse_schedule({"steps": ch.schedule}, name)


# --- bad input: exact messages ----------------------------------------------------------------

def test_unknown_challenge(challenges):
    with pytest.raises(ChallengeError) as e:
        challenges.select("D9")
    assert str(e.value) == ("challenges.yaml: unknown challenge 'D9' "
                            "(expected one of: B1, B2, D1, D2, D3, D4, P1, P2, V1)")


def test_unknown_variant(challenges):
    with pytest.raises(ChallengeError) as e:
        challenges.select("D3", "v3")
    assert str(e.value) == "challenges.yaml: challenges.D3: unknown variant 'v3' (expected one of: v1, v2)"


@pytest.mark.parametrize("seed", ["-1", "abc", -2, 1.5, "", True])
def test_bad_seed(challenges, seed):
    with pytest.raises(ChallengeError) as e:
        challenges.select("D3", "v1", seed)
    assert str(e.value) == "seed: expected an integer >= 0, got %r" % (seed,)


def test_seed_given_as_text_like_roslaunch(challenges):
    assert challenges.select("D3", "v1", "12")[2] == 12


def test_a_seed_that_cannot_place_the_boxes_is_an_error_naming_it():
    zone = {"loop": "north", "from_deg": 0.0, "to_deg": 270.0}
    with pytest.raises(ChallengeError) as e:
        co.random_obstacles(42, (20.0, 250.0), [zone])
    assert str(e.value) == ("seed 42: cannot place the obstacle of the north loop in 20..250 deg away from the "
                            "working zone and the tunnel (200 attempts)")


def load_text(text):
    return parse_challenges(yaml.safe_load(text), "/some/where/bad.yaml")


def good_data():
    with open(CHALLENGES_FILE) as f:
        return yaml.safe_load(f)


@pytest.mark.parametrize("edit,message", [
    (lambda d: d.update(format="conde_challenges/2"),
     "bad.yaml: format: expected 'conde_challenges/1', got 'conde_challenges/2'"),
    (lambda d: d.update(extra=1),
     "bad.yaml: top level: unknown key 'extra' (expected one of: format, base_world, start_poses, schedules, "
     "challenges, placement)"),
    (lambda d: d["challenges"]["D3"]["variants"]["v1"]["obstacles"][0].update(lane="middle"),
     "bad.yaml: challenges.D3.variants.v1.obstacles[0].lane: expected one of inner, outer, got 'middle'"),
    (lambda d: d["challenges"]["D3"]["variants"]["v1"]["obstacles"][1].update(angle_deg=300),
     "bad.yaml: challenges.D3.variants.v1.obstacles[1].angle_deg: expected a number in [0, 270], got 300"),
    (lambda d: d["challenges"]["D1"].update(schedule="nope"),
     "bad.yaml: challenges.D1.schedule: expected one of go, two_laps, panel_orders, park, got 'nope'"),
    (lambda d: d["challenges"]["D1"].pop("time_limit_s"),
     "bad.yaml: challenges.D1: missing key 'time_limit_s'"),
    (lambda d: d["challenges"]["P2"]["variants"]["v1"].update(flying_boxes={}),
     "bad.yaml: challenges.P2.variants.v1: unknown key 'flying_boxes' (expected one of: obstacles, "
     "working_zone, tunnel, parallel_boxes, occupied_bay, signs)"),
    (lambda d: d["schedules"]["go"][1].update(signal="jump"),
     "bad.yaml: schedules.go[1].signal: expected one of none, left, right, forward, stop, end_of_trial, "
     "parking, got 'jump'"),
    (lambda d: d["start_poses"]["crosswalk"]["conde"].update(xyz=[1, 2]),
     "bad.yaml: start_poses.crosswalk.conde.xyz: expected [x, y, z] in metres, got [1, 2]"),
    (lambda d: d["challenges"]["D4"]["variants"]["v1"]["tunnel"].update(from_deg=210),
     "bad.yaml: challenges.D4.variants.v1.tunnel: from_deg 210 must be below to_deg 200"),
    (lambda d: d["challenges"]["B2"]["random"].update(occupied_bay=["east"]),
     "bad.yaml: challenges.B2.random.occupied_bay[0]: expected one of north, south, got 'east'"),
])
def test_bad_description_messages_name_file_and_key(edit, message):
    data = good_data()
    edit(data)
    with pytest.raises(ChallengeError) as e:
        parse_challenges(data, "/some/where/bad.yaml")
    assert str(e.value) == message


def test_unreadable_file_names_the_path(tmp_path):
    missing = str(tmp_path / "none.yaml")
    with pytest.raises(ChallengeError) as e:
        load_challenges(missing)
    assert str(e.value) == "%s: cannot read the challenge file: No such file or directory" % missing


def test_top_view_shows_the_boxes_where_they_are(tmp_path):
    from conde_worlds.challenge_render import TOP_VIEW_PX_PER_M, write_top_view
    from conde_worlds.track_render import world_to_pixel
    paths = write_challenge("D3", "v1", 0, str(tmp_path))
    png = str(tmp_path / "top.png")
    write_top_view(paths["world"], png)
    img = cv2.cvtColor(cv2.imread(png), cv2.COLOR_BGR2RGB)
    world = yaml.safe_load(open(paths["world"]))
    assert img.shape[:2] == (int(round(16.7 * TOP_VIEW_PX_PER_M)), int(round(7.45 * TOP_VIEW_PX_PER_M)))
    for box in (o for o in world["objects"] if o["name"].startswith("obstacle_")):
        col, row = world_to_pixel(*box["pose"]["xyz"][:2], TOP_VIEW_PX_PER_M, world["ground"]["x_range_m"],
                                  world["ground"]["y_range_m"])
        assert list(img[int(row), int(col)]) == [0, 255, 0]
