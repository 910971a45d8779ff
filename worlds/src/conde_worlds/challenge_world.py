"""A challenge's world, schedule and description, generated from the track and challenges.yaml.

Pure Python, no ROS.  :func:`layout` resolves a (challenge, variant, seed) into the parameters
of its features (seed 0: the variant's fixed layout; seed N > 0: drawn with random.Random(N)
from the challenge's `random` section); :func:`challenge_world` turns that into a world-file
mapping (the base world's ground, panels and physics plus the features' objects and one spawn
pose per robot); :func:`write_challenge` writes the world, the sign textures, the panel schedule
and a summary into one directory.

A track seed N > 0 puts the challenge on a varied track (track_variation.py): its texture and
geometry are written beside the world, every object is built on the varied lines, and the base
world's panels and the start poses are carried over with TrackDimensions.map_xy.  The summary
names the track seed and its measures (`track`).
"""

import copy
import os
from typing import Dict, Optional, Tuple

import yaml

from . import challenge_objects as co
from . import placement
from .challenges import Challenges, load_challenges, parse_seed
from .track_render import texture_ranges
from .track_variation import NOMINAL, TrackDimensions, track_dimensions

WORLD_FILE = "world.yaml"
SCHEDULE_FILE = "schedule.yaml"
SUMMARY_FILE = "challenge.yaml"
TEXTURE_DIR = "textures"


def layout(challenges: Challenges, challenge: str, variant: Optional[str] = None, seed=0) -> Tuple[str, str, int, dict]:
    """(challenge, variant, seed, {feature: parameters}) with the seed applied."""
    ch, variant, seed = challenges.select(challenge, variant, seed)
    features = copy.deepcopy(ch.variants[variant])
    if seed:
        rnd = ch.random
        if "obstacles" in rnd:
            keep_clear = [features[k] for k in ("working_zone", "tunnel") if k in features]
            features["obstacles"] = co.random_obstacles(seed, rnd["obstacles"]["angle_deg"], keep_clear)
        if "occupied_bay" in rnd:
            import random
            features["occupied_bay"] = random.Random(seed).choice(rnd["occupied_bay"])
        if "signs" in rnd:
            features["signs"] = "shuffle"
    return challenge, variant, seed, features


def objects_of(features: dict, seed: int, dims: TrackDimensions = NOMINAL) -> Tuple[list, Dict[str, str]]:
    """(world objects, {texture file name: sign}) of the features on the track of measures dims."""
    objects, textures = [], {}
    if "obstacles" in features:
        objects += co.obstacles(features["obstacles"], dims)
    if "working_zone" in features:
        objects += co.working_zone(features["working_zone"], dims)
    if "tunnel" in features:
        objects += co.tunnel(features["tunnel"], dims)
    if "parallel_boxes" in features:
        objects += co.parallel_boxes(features["parallel_boxes"], dims)
    if "occupied_bay" in features:
        objects += co.bay_box(features["occupied_bay"], dims)
    if "signs" in features:
        from . import traffic_signs  # OpenCV: imported only when drawn (launch files run the generator 3 times)
        order = co.sign_order(traffic_signs.SIGNS, seed if features["signs"] == "shuffle" else 0)
        for i, sign in enumerate(order):
            name = "%s/sign_%s.png" % (TEXTURE_DIR, sign)
            textures[name] = sign
            objects.append(co.sign_object(i, sign, name, dims))
    return objects, textures


def base_world_path(challenges: Challenges) -> str:
    return os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(challenges.path))), "worlds",
                        challenges.base_world + ".world.yaml")


def _carried_over(xyz, dims: TrackDimensions) -> list:
    x, y = dims.map_xy(xyz[0], xyz[1])
    return [round(x, 4), round(y, 4)] + list(xyz[2:]) if not dims.is_nominal else list(xyz)


def start_poses(start: Dict[str, dict], dims: TrackDimensions = NOMINAL) -> Dict[str, dict]:
    """{robot: {xyz, yaw}} of a challenge's start on the track dims."""
    return {robot: {"xyz": _carried_over(pose["xyz"], dims), "yaw": pose["yaw"]} for robot, pose in start.items()}


def challenge_world(challenges: Challenges, challenge: str, variant: Optional[str] = None, seed=0, track_seed=0,
                    placement_seed=0):
    """(world mapping, {texture file: sign}, resolved (challenge, variant, seed, features)).
    A placement seed N > 0 moves the start poses within the start area (placement.py). On a varied
    track (track_seed > 0) the ground texture is track_files.track_file_names(track_seed)[0],
    relative to the world file's directory."""
    resolved = layout(challenges, challenge, variant, seed)
    name, variant, seed, features = resolved
    dims = track_dimensions(parse_seed(track_seed, "track seed"))
    with open(base_world_path(challenges)) as f:
        world = yaml.safe_load(f)
    ch = challenges.challenges[name]
    world["name"] = "challenge_%s_%s_seed%d" % (name, variant, seed)
    texture = world["ground"].get("texture")
    if not dims.is_nominal:
        from .track_files import track_file_names
        world["name"] += "_track%d" % dims.track_seed
        x_range, y_range = texture_ranges(dims)
        world["ground"].update(texture=track_file_names(dims.track_seed)[0].replace(os.sep, "/"),
                               x_range_m=list(x_range), y_range_m=list(y_range))
        for obj in world.get("objects") or []:  # the panels stay above the varied lanes
            obj["pose"]["xyz"] = _carried_over(obj["pose"]["xyz"], dims)
    elif texture and not texture.startswith(("package://", "/")):
        # The base world's texture, relative to worlds/, as a package path (the generated
        # world lives elsewhere).
        world["ground"]["texture"] = "package://conde_worlds/" + os.path.normpath(os.path.join("worlds", texture))
    objects, textures = objects_of(features, seed, dims)
    world["objects"] = list(world.get("objects") or []) + objects
    placement_seed = parse_seed(placement_seed, "placement seed")
    world["spawn"] = placement.placed_poses(start_poses(ch.start, dims), placement_seed, challenges.start_area)
    if placement_seed:
        world["name"] += "_place%d" % placement_seed
    if "tunnel" in features:
        world["light_regions"] = [co.tunnel_light_region(features["tunnel"], dims)]
    return world, textures, resolved


def default_output_dir(challenge: str, variant: str, seed: int, track_seed: int = 0, placement_seed: int = 0) -> str:
    """$ROS_HOME/conde_challenges/<challenge>_<variant>_seed<seed>_track<track_seed>[_place<placement_seed>]
    (ROS_HOME defaults to ~/.ros; the placement part only for placement seeds > 0)."""
    ros_home = os.environ.get("ROS_HOME") or os.path.join(os.path.expanduser("~"), ".ros")
    name = "%s_%s_seed%d_track%d" % (challenge, variant, seed, track_seed)
    if placement_seed:
        name += "_place%d" % placement_seed
    return os.path.join(ros_home, "conde_challenges", name)


def write_challenge(challenge: str, variant: Optional[str] = None, seed=0, output_dir: Optional[str] = None,
                    challenges_path: Optional[str] = None, track_seed=0, placement_seed=0) -> Dict[str, str]:
    """Writes world.yaml, textures/, schedule.yaml and challenge.yaml (and, on a varied track,
    the track's texture and geometry); returns their paths ({"world", "schedule", "summary",
    "dir"})."""
    challenges = load_challenges(challenges_path)
    track_seed = parse_seed(track_seed, "track seed")
    placement_seed = parse_seed(placement_seed, "placement seed")
    world, textures, (name, variant, seed, features) = challenge_world(challenges, challenge, variant, seed,
                                                                       track_seed, placement_seed)
    ch = challenges.challenges[name]
    dims = track_dimensions(track_seed)
    out = output_dir or default_output_dir(name, variant, seed, track_seed, placement_seed)
    os.makedirs(os.path.join(out, TEXTURE_DIR), exist_ok=True)
    if textures:
        from . import traffic_signs
        for file_name, sign in textures.items():
            traffic_signs.write_sign(sign, os.path.join(out, file_name))
    if track_seed:
        from .track_files import track_file_names, write_track_files
        # launch/challenge.launch runs the generator three times: render the texture once.
        write_track_files(out, track_seed, reuse=True)
    paths = {"dir": out, "world": os.path.join(out, WORLD_FILE), "schedule": os.path.join(out, SCHEDULE_FILE),
             "summary": os.path.join(out, SUMMARY_FILE)}
    command = "scripts/generate_challenge %s --variant %s --seed %d" % (name, variant, seed)
    if track_seed:
        command += " --track-seed %d" % track_seed
    if placement_seed:
        command += " --placement-seed %d" % placement_seed
    header = ("# Generated by conde_worlds (%s) from "
              "challenges/challenges.yaml and the track geometry; do not edit.\n" % command)
    _write(paths["world"], header + _dump(world, width=110))
    _write(paths["schedule"], header + _dump({"steps": ch.schedule}))
    summary = {"challenge": name, "what": ch.what, "variant": variant, "seed": seed,
               "time_limit_s": ch.time_limit_s, "start": world["spawn"], "schedule": ch.schedule_name,
               "features": features, "world_file": paths["world"], "schedule_file": paths["schedule"],
               "track_seed": track_seed, "track": dims.summary(), "placement_seed": placement_seed,
               "placement": placement.offset(placement_seed, challenges.start_area).summary()}
    if track_seed:
        summary["track_geometry_file"] = os.path.join(out, track_file_names(track_seed)[1])
    _write(paths["summary"], header + _dump(summary))
    return paths


class _Dumper(yaml.SafeDumper):
    """Writes repeated values (the shared colours) in full instead of as YAML aliases."""

    def ignore_aliases(self, data):
        return True


def _dump(data, **kwargs):
    return yaml.dump(data, Dumper=_Dumper, sort_keys=False, default_flow_style=None, **kwargs)


def _write(path, text):
    # Write then rename, so a simulator starting at the same time never reads half a file.
    tmp = path + ".tmp%d" % os.getpid()
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)
