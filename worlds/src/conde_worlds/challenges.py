"""The challenge descriptions (challenges/challenges.yaml): loading, strict validation, selection.

Pure Python, no ROS.  A description names, per challenge, its start pose, its signalling-panel
schedule, its time limit and its variants; a variant is a mapping of feature name -> parameters
(the features are built by challenge_objects.py).  Every error is a ChallengeError whose message
names the file and the key, e.g.

    challenges.yaml: challenges.D3.variants.v1.obstacles[0].lane: expected one of inner, outer, got 'middle'
"""

import math
import os
from dataclasses import dataclass, field
from typing import Dict, List, Optional

from conde_common.config_files import parse_yaml, read_text

from .placement import AREA_LIMITS, NOMINAL_AREA, StartArea

FORMAT = "conde_challenges/1"
SIGNALS = ("none", "left", "right", "forward", "stop", "end_of_trial", "parking")
LOOPS = ("north", "south")
LANES = ("inner", "outer")
BAYS = ("north", "south")
#: The loop arc runs 270 deg from the top (north) / bottom (south) end of the straight.
LOOP_ARC_DEG = 270.0
#: Robots that get a start pose in every world (conde_description xacro names).
ROBOTS = ("conde", "major_alvega")


class ChallengeError(ValueError):
    """Invalid challenge description or selection; the message names the file and the key."""


@dataclass
class Challenge:
    name: str
    what: str
    start: Dict[str, dict]           # robot -> {xyz: [x, y, z] m, yaw: rad}
    schedule_name: str
    schedule: List[dict]             # [{at_s, signal}]
    time_limit_s: float
    variants: Dict[str, dict]        # variant -> {feature: parameters}
    random: Dict[str, object] = field(default_factory=dict)


@dataclass
class Challenges:
    path: str
    base_world: str
    challenges: Dict[str, Challenge]
    start_area: StartArea = NOMINAL_AREA   # where placement seeds put the robot (placement.py)

    def select(self, challenge: str, variant: Optional[str] = None, seed=0):
        """(Challenge, variant name, seed) after checking all three; variant None = the first."""
        where = os.path.basename(self.path)
        if challenge not in self.challenges:
            raise ChallengeError("%s: unknown challenge %r (expected one of: %s)"
                                 % (where, challenge, ", ".join(sorted(self.challenges))))
        ch = self.challenges[challenge]
        if variant in (None, ""):
            variant = next(iter(ch.variants))
        if variant not in ch.variants:
            raise ChallengeError("%s: challenges.%s: unknown variant %r (expected one of: %s)"
                                 % (where, challenge, variant, ", ".join(ch.variants)))
        return ch, variant, parse_seed(seed)


def parse_seed(seed, what: str = "seed") -> int:
    """The seed as an int >= 0 (also from a string such as roslaunch passes); `what` names it
    in the error."""
    value = seed
    if isinstance(seed, str):
        try:
            value = int(seed.strip(), 10)
        except ValueError:
            value = None
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        raise ChallengeError("%s: expected an integer >= 0, got %r" % (what, seed))
    return value


def default_path() -> str:
    """challenges/challenges.yaml of this package: beside the sources (source tree and devel
    space), else in the installed share directory (found with rospkg)."""
    here = os.path.dirname(os.path.abspath(__file__))
    beside = os.path.normpath(os.path.join(here, "..", "..", "challenges", "challenges.yaml"))
    if os.path.isfile(beside):
        return beside
    try:
        import rospkg
        return os.path.join(rospkg.RosPack().get_path("conde_worlds"), "challenges", "challenges.yaml")
    except Exception:  # rospkg missing or the package not on ROS_PACKAGE_PATH: report the first path
        return beside


def load_challenges(path: Optional[str] = None) -> Challenges:
    """Reads and validates a challenge file; raises ChallengeError."""
    path = path or default_path()
    where = os.path.basename(path)
    text = read_text(path, ChallengeError, "the challenge file")
    return parse_challenges(parse_yaml(text, where, ChallengeError, "not valid YAML"), path)


# --- validation helpers (each raises with "<file>: <key>: ...") ---------------------------------

class _V:
    def __init__(self, where):
        self.where = where

    def fail(self, key, message):
        raise ChallengeError("%s: %s: %s" % (self.where, key, message))

    def mapping(self, value, key, required=(), optional=(), any_keys=False):
        if not isinstance(value, dict):
            self.fail(key, "expected a mapping, got %r" % (value,))
        if any_keys:
            return value
        allowed = tuple(required) + tuple(optional)
        for k in value:
            if k not in allowed:
                self.fail(key, "unknown key %r (expected one of: %s)" % (k, ", ".join(allowed)))
        for k in required:
            if k not in value:
                self.fail(key, "missing key %r" % k)
        return value

    def number(self, value, key, lo=-math.inf, hi=math.inf):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            self.fail(key, "expected a finite number, got %r" % (value,))
        if not lo <= value <= hi:
            self.fail(key, "expected a number in [%g, %g], got %g" % (lo, hi, value))
        return float(value)

    def choice(self, value, key, choices):
        if value not in choices:
            self.fail(key, "expected one of %s, got %r" % (", ".join(choices), value))
        return value

    def string(self, value, key):
        if not isinstance(value, str) or not value:
            self.fail(key, "expected a non-empty string, got %r" % (value,))
        return value

    def pose(self, value, key):
        self.mapping(value, key, ("xyz",), ("yaw",))
        xyz = value["xyz"]
        if not isinstance(xyz, list) or len(xyz) != 3:
            self.fail(key + ".xyz", "expected [x, y, z] in metres, got %r" % (xyz,))
        return {"xyz": [self.number(v, "%s.xyz[%d]" % (key, i)) for i, v in enumerate(xyz)],
                "yaw": self.number(value.get("yaw", 0.0), key + ".yaw")}

    def arc_range(self, lo, hi, key):
        a = self.number(lo, key + ".from_deg", 0.0, LOOP_ARC_DEG)
        b = self.number(hi, key + ".to_deg", 0.0, LOOP_ARC_DEG)
        if not a < b:
            self.fail(key, "from_deg %g must be below to_deg %g" % (a, b))
        return a, b


def _check_feature(v: _V, name, value, key):
    """Validates one feature of a variant and returns it normalised."""
    if name == "obstacles":
        if not isinstance(value, list) or not value:
            v.fail(key, "expected a non-empty list of {loop, lane, angle_deg}")
        out = []
        for i, ob in enumerate(value):
            k = "%s[%d]" % (key, i)
            v.mapping(ob, k, ("loop", "lane", "angle_deg"))
            out.append({"loop": v.choice(ob["loop"], k + ".loop", LOOPS),
                        "lane": v.choice(ob["lane"], k + ".lane", LANES),
                        "angle_deg": v.number(ob["angle_deg"], k + ".angle_deg", 0.0, LOOP_ARC_DEG)})
        return out
    if name == "working_zone":
        v.mapping(value, key, ("loop", "lane", "from_deg", "to_deg"))
        a, b = v.arc_range(value["from_deg"], value["to_deg"], key)
        return {"loop": v.choice(value["loop"], key + ".loop", LOOPS),
                "lane": v.choice(value["lane"], key + ".lane", LANES), "from_deg": a, "to_deg": b}
    if name == "tunnel":
        v.mapping(value, key, ("loop", "from_deg", "to_deg"))
        a, b = v.arc_range(value["from_deg"], value["to_deg"], key)
        return {"loop": v.choice(value["loop"], key + ".loop", LOOPS), "from_deg": a, "to_deg": b}
    if name == "parallel_boxes":
        v.mapping(value, key, ("gap_m",))
        return {"gap_m": v.number(value["gap_m"], key + ".gap_m", 0.3, 1.8)}
    if name == "occupied_bay":
        return v.choice(value, key, BAYS)
    if name == "signs":
        return v.choice(value, key, ("identity",))
    v.fail(key, "unknown feature (expected one of: %s)" % ", ".join(FEATURES))


FEATURES = ("obstacles", "working_zone", "tunnel", "parallel_boxes", "occupied_bay", "signs")


def _check_random(v: _V, value, key):
    v.mapping(value, key, optional=("obstacles", "occupied_bay", "signs"))
    out = {}
    if "obstacles" in value:
        k = key + ".obstacles"
        v.mapping(value["obstacles"], k, ("angle_deg",))
        rng = value["obstacles"]["angle_deg"]
        if not isinstance(rng, list) or len(rng) != 2:
            v.fail(k + ".angle_deg", "expected [from, to] in degrees, got %r" % (rng,))
        out["obstacles"] = {"angle_deg": v.arc_range(rng[0], rng[1], k + ".angle_deg")}
    if "occupied_bay" in value:
        bays = value["occupied_bay"]
        if not isinstance(bays, list) or not bays:
            v.fail(key + ".occupied_bay", "expected a non-empty list of bays, got %r" % (bays,))
        out["occupied_bay"] = [v.choice(b, "%s.occupied_bay[%d]" % (key, i), BAYS) for i, b in enumerate(bays)]
    if "signs" in value:
        out["signs"] = v.choice(value["signs"], key + ".signs", ("shuffle",))
    return out


def parse_challenges(data, path: str) -> Challenges:
    v = _V(os.path.basename(path))
    v.mapping(data, "top level", ("format", "base_world", "start_poses", "schedules", "challenges"), ("placement",))
    if data["format"] != FORMAT:
        v.fail("format", "expected %r, got %r" % (FORMAT, data["format"]))
    base_world = v.string(data["base_world"], "base_world")

    starts = v.mapping(data["start_poses"], "start_poses", any_keys=True)
    for name, per_robot in starts.items():
        v.mapping(per_robot, "start_poses.%s" % name, ROBOTS)
        for robot in ROBOTS:
            per_robot[robot] = v.pose(per_robot[robot], "start_poses.%s.%s" % (name, robot))

    schedules = v.mapping(data["schedules"], "schedules", any_keys=True)
    for name, steps in schedules.items():
        key = "schedules.%s" % name
        if not isinstance(steps, list) or not steps:
            v.fail(key, "expected a non-empty list of {at_s, signal}")
        last = 0.0
        for i, step in enumerate(steps):
            k = "%s[%d]" % (key, i)
            v.mapping(step, k, ("at_s", "signal"))
            at = v.number(step["at_s"], k + ".at_s", 0.0)
            if at < last:
                v.fail(k + ".at_s", "%g is before the previous step's %g (times must not decrease)" % (at, last))
            last = at
            v.choice(step["signal"], k + ".signal", SIGNALS)

    challenges = {}
    for name, ch in v.mapping(data["challenges"], "challenges", any_keys=True).items():
        key = "challenges.%s" % name
        v.mapping(ch, key, ("what", "start", "schedule", "time_limit_s", "variants"), ("random",))
        v.choice(ch["start"], key + ".start", tuple(starts))
        v.choice(ch["schedule"], key + ".schedule", tuple(schedules))
        variants = v.mapping(ch["variants"], key + ".variants", any_keys=True)
        if not variants:
            v.fail(key + ".variants", "expected at least one variant")
        checked = {}
        for vname, features in variants.items():
            vkey = "%s.variants.%s" % (key, vname)
            v.mapping(features or {}, vkey, optional=FEATURES)
            checked[vname] = {f: _check_feature(v, f, p, "%s.%s" % (vkey, f)) for f, p in (features or {}).items()}
        challenges[name] = Challenge(
            name=name, what=v.string(ch["what"], key + ".what"), start=starts[ch["start"]],
            schedule_name=ch["schedule"], schedule=schedules[ch["schedule"]],
            time_limit_s=v.number(ch["time_limit_s"], key + ".time_limit_s", 1.0),
            variants=checked, random=_check_random(v, ch.get("random", {}), key + ".random"))
    return Challenges(path=path, base_world=base_world, challenges=challenges,
                      start_area=_check_placement(v, data.get("placement", {}), "placement"))


def _check_placement(v: _V, value, key) -> StartArea:
    """The start area of placement seeds: each axis a range [lo, hi] inside AREA_LIMITS."""
    v.mapping(value, key, optional=tuple(AREA_LIMITS))
    ranges = {}
    for axis, (lo_limit, hi_limit) in AREA_LIMITS.items():
        rng = value.get(axis, [0.0, 0.0])
        k = "%s.%s" % (key, axis)
        if not isinstance(rng, list) or len(rng) != 2:
            v.fail(k, "expected [lo, hi], got %r" % (rng,))
        lo, hi = (v.number(r, k, lo_limit, hi_limit) for r in rng)
        if lo > hi:
            v.fail(k, "lo %g must not be above hi %g" % (lo, hi))
        ranges[axis] = (lo, hi)
    return StartArea(**ranges)
