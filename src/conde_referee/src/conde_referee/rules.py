"""The referee's rules file: penalty values [points], the score formula's constants and the
judging thresholds. Pure Python, no ROS.

Validated strictly: unknown or missing keys and values of the wrong type are a RulesError whose
message names the file and the key, e.g.

    rules.yaml: penalties.line_touch: expected a number >= 0, got 'ten'
"""
import math
import os
from dataclasses import dataclass
from typing import Dict

from conde_common.config_files import parse_yaml, read_text

FORMAT = "conde_referee_rules/1"
PENALTIES = ("false_start", "line_touch", "leave_road", "wrong_direction", "stop_not_respected",
             "stopped_outside_zone", "wrong_branch", "collision", "parking_line_touch", "sign_wrong")
SCORING = ("laps", "points_per_half_lap", "reference_half_lap_s", "parking_points", "parking_stay_s",
           "sign_points", "repeat_debounce_s")
JUDGING = ("stop_zone_depth_m", "standstill_s", "standstill_tolerance_m", "sign_report_radius_m")


class RulesError(ValueError):
    """Invalid rules file; the message names the file and the key."""


@dataclass(frozen=True)
class Rules:
    name: str
    penalties: Dict[str, float]   # event kind -> points
    scoring: Dict[str, float]
    judging: Dict[str, float]


def default_path() -> str:
    """config/rules_2019_placeholder.yaml of this package (source tree, else via rospkg)."""
    here = os.path.dirname(os.path.abspath(__file__))
    beside = os.path.normpath(os.path.join(here, "..", "..", "config", "rules_2019_placeholder.yaml"))
    if os.path.isfile(beside):
        return beside
    import rospkg
    return os.path.join(rospkg.RosPack().get_path("conde_referee"), "config", "rules_2019_placeholder.yaml")


def load_rules(path=None) -> Rules:
    path = path or default_path()
    where = os.path.basename(path)
    text = read_text(path, RulesError, "the rules file")
    return parse_rules(parse_yaml(text, where, RulesError, "not valid YAML"), where)


def _fail(where, key, message):
    raise RulesError("%s: %s: %s" % (where, key, message))


def _section(data, where, key, names):
    value = data[key]
    if not isinstance(value, dict):
        _fail(where, key, "expected a mapping, got %r" % (value,))
    for k in value:
        if k not in names:
            _fail(where, key, "unknown key %r (expected one of: %s)" % (k, ", ".join(names)))
    out = {}
    for k in names:
        if k not in value:
            _fail(where, key, "missing key %r" % k)
        v = value[k]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
            _fail(where, "%s.%s" % (key, k), "expected a number >= 0, got %r" % (v,))
        out[k] = float(v)
    return out


def parse_rules(data, where="rules") -> Rules:
    if not isinstance(data, dict):
        _fail(where, "top level", "expected a mapping, got %r" % (data,))
    top = ("format", "name", "penalties", "scoring", "judging")
    for k in data:
        if k not in top:
            _fail(where, "top level", "unknown key %r (expected one of: %s)" % (k, ", ".join(top)))
    for k in top:
        if k not in data:
            _fail(where, "top level", "missing key %r" % k)
    if data["format"] != FORMAT:
        _fail(where, "format", "expected %r, got %r" % (FORMAT, data["format"]))
    if not isinstance(data["name"], str) or not data["name"]:
        _fail(where, "name", "expected a non-empty string, got %r" % (data["name"],))
    scoring = _section(data, where, "scoring", SCORING)
    if scoring["laps"] < 1 or scoring["laps"] != int(scoring["laps"]):
        _fail(where, "scoring.laps", "expected a whole number >= 1, got %r" % (data["scoring"]["laps"],))
    return Rules(name=data["name"], penalties=_section(data, where, "penalties", PENALTIES), scoring=scoring,
                 judging=_section(data, where, "judging", JUDGING))
