"""The tournament file (YAML), validated, and the jobs it asks for (pure Python, no ROS).

    name: Robotics class 2026                # shown on the leaderboard
    teams:
      - name: reference                      # the reference Conde stack, unchanged
      - name: team_a
        launch: team_a/control.launch        # starts the team's nodes (relative to this file)
        replaces: [control]                  # reference nodes it replaces: tracking semaphore decision control
      - name: team_b
        overlay: /home/b/catkin_ws/devel/setup.bash   # a workspace whose packages shadow ours
        lockstep_config: team_b/lockstep.yaml          # which topics answer which (default: the reference stack's)
    challenges:
      - {name: D1, variants: [v1], seeds: [0, 1]}
      - {name: D3}                           # variants: the challenge's first; seeds: [0]
    engines: [ode, bullet]                   # default [ode]
    repeats: 1                               # each job run this many times (default 1)
    limits: {sim_s: 120, wall_s: 900}        # per job: simulated [s] (0 = the challenge's own end), wall clock [s]
    cpus_per_job: 1                          # CPUs one job takes (local pool size, Ray's num_cpus)

Unknown keys, wrong types and missing names are errors (TournamentError) naming the file and the
key. A team's launch file that does not exist is not an error here: that team's jobs fail with
the reason (the other teams still run).
"""
import os
from dataclasses import dataclass, field
from typing import List, Optional, Tuple

from conde_common import config_files

REFERENCE_NODES = ("tracking", "semaphore", "decision", "control")
ENGINES = ("ode", "bullet")


class TournamentError(ValueError):
    """A tournament file that cannot be used; the message names the file and the key."""


@dataclass(frozen=True)
class Team:
    name: str
    launch: str = ""            # absolute path of the team's launch file, '' = none
    replaces: Tuple[str, ...] = ()
    overlay: str = ""           # absolute path of a workspace's setup.bash, '' = none
    lockstep_config: str = ""   # absolute path, '' = the reference stack's


@dataclass(frozen=True)
class Challenge:
    name: str
    variants: Tuple[str, ...] = ("",)   # '' = the challenge's first variant
    seeds: Tuple[int, ...] = (0,)


@dataclass(frozen=True)
class Job:
    team: Team
    challenge: str
    variant: str
    seed: int
    engine: str
    repeat: int

    @property
    def job_id(self) -> str:
        """Folder name of the job: unique in its tournament, stable across runs (resume)."""
        return "%s__%s_%s_seed%d__%s__r%d" % (self.team.name, self.challenge, self.variant or "default",
                                              self.seed, self.engine, self.repeat)


@dataclass
class Tournament:
    name: str
    teams: List[Team]
    challenges: List[Challenge]
    engines: List[str] = field(default_factory=lambda: ["ode"])
    repeats: int = 1
    sim_limit_s: float = 0.0
    wall_limit_s: float = 900.0
    cpus_per_job: int = 1
    path: str = ""

    def jobs(self) -> List[Job]:
        """Every (team, challenge, variant, seed, engine, repeat), in a stable order."""
        return [Job(team, c.name, variant, seed, engine, repeat)
                for team in self.teams for c in self.challenges for variant in c.variants for seed in c.seeds
                for engine in self.engines for repeat in range(self.repeats)]


def _check_keys(where: str, mapping, allowed, required=()):
    if not isinstance(mapping, dict):
        raise TournamentError("%s: expected a mapping, got %r" % (where, mapping))
    for key in mapping:
        if key not in allowed:
            raise TournamentError("%s: unknown key '%s' (allowed: %s)" % (where, key, ", ".join(allowed)))
    for key in required:
        if key not in mapping:
            raise TournamentError("%s: missing key '%s'" % (where, key))


def _name(where: str, value) -> str:
    if not isinstance(value, str) or not value or not all(ch.isalnum() or ch in "_-" for ch in value):
        raise TournamentError("%s: expected a name of letters, digits, '_' or '-', got %r" % (where, value))
    return value


def _number(where: str, value, minimum: float, integer: bool = False):
    kinds = (int,) if integer else (int, float)
    if isinstance(value, bool) or not isinstance(value, kinds) or value < minimum:
        raise TournamentError("%s: expected %s >= %g, got %r" % (where, "an integer" if integer else "a number",
                                                                 minimum, value))
    return value


def _list(where: str, value) -> list:
    if not isinstance(value, list) or not value:
        raise TournamentError("%s: expected a non-empty list, got %r" % (where, value))
    return value


def _path(base_dir: str, value, where: str) -> str:
    if not isinstance(value, str) or not value:
        raise TournamentError("%s: expected a file path, got %r" % (where, value))
    return os.path.normpath(os.path.join(base_dir, os.path.expanduser(value)))


def _team(where: str, entry, base_dir: str) -> Team:
    _check_keys(where, entry, ("name", "launch", "replaces", "overlay", "lockstep_config"), ("name",))
    name = _name(where + ".name", entry["name"])
    replaces = entry.get("replaces", [])
    if not isinstance(replaces, list) or any(r not in REFERENCE_NODES for r in replaces):
        raise TournamentError("%s.replaces: expected a list of %s, got %r"
                              % (where, ", ".join(REFERENCE_NODES), replaces))
    launch = _path(base_dir, entry["launch"], where + ".launch") if "launch" in entry else ""
    if replaces and not launch:
        raise TournamentError("%s.replaces: the team replaces %s but has no 'launch' file to start its own"
                              % (where, ", ".join(replaces)))
    overlay = _path(base_dir, entry["overlay"], where + ".overlay") if "overlay" in entry else ""
    lockstep = _path(base_dir, entry["lockstep_config"], where + ".lockstep_config") \
        if "lockstep_config" in entry else ""
    return Team(name, launch, tuple(replaces), overlay, lockstep)


def _challenge(where: str, entry) -> Challenge:
    _check_keys(where, entry, ("name", "variants", "seeds"), ("name",))
    name = _name(where + ".name", entry["name"])
    variants = tuple(_name(where + ".variants", v) for v in _list(where + ".variants", entry["variants"])) \
        if "variants" in entry else ("",)
    seeds = tuple(_number(where + ".seeds", s, 0, integer=True) for s in _list(where + ".seeds", entry["seeds"])) \
        if "seeds" in entry else (0,)
    return Challenge(name, variants, seeds)


def parse_tournament(data, path: str = "<tournament>") -> Tournament:
    """The Tournament of a parsed YAML document; relative paths are resolved beside `path`."""
    where = path
    _check_keys(where, data, ("name", "teams", "challenges", "engines", "repeats", "limits", "cpus_per_job"),
                ("teams", "challenges"))
    base_dir = os.path.dirname(os.path.abspath(path))
    teams = [_team("%s: teams[%d]" % (where, i), t, base_dir)
             for i, t in enumerate(_list(where + ": teams", data["teams"]))]
    names = [t.name for t in teams]
    for name in names:
        if names.count(name) > 1:
            raise TournamentError("%s: teams: the name '%s' is used twice" % (where, name))
    challenges = [_challenge("%s: challenges[%d]" % (where, i), c)
                  for i, c in enumerate(_list(where + ": challenges", data["challenges"]))]
    engines = _list(where + ": engines", data.get("engines", ["ode"]))
    for engine in engines:
        if engine not in ENGINES:
            raise TournamentError("%s: engines: unknown engine %r (expected %s)"
                                  % (where, engine, " or ".join(ENGINES)))
    limits = data.get("limits", {})
    _check_keys(where + ": limits", limits, ("sim_s", "wall_s"))
    title = data.get("name", os.path.splitext(os.path.basename(path))[0])
    if not isinstance(title, str):
        raise TournamentError("%s: name: expected a string, got %r" % (where, title))
    return Tournament(
        name=title, teams=teams, challenges=challenges, engines=list(engines),
        repeats=_number(where + ": repeats", data.get("repeats", 1), 1, integer=True),
        sim_limit_s=float(_number(where + ": limits.sim_s", limits.get("sim_s", 0.0), 0)),
        wall_limit_s=float(_number(where + ": limits.wall_s", limits.get("wall_s", 900.0), 1)),
        cpus_per_job=_number(where + ": cpus_per_job", data.get("cpus_per_job", 1), 1, integer=True),
        path=os.path.abspath(path))


def check_challenges(tournament: Tournament, catalogue) -> None:
    """Checks every challenge and variant against the challenge catalogue (conde_worlds
    load_challenges()) and names each default variant ('') explicitly."""
    from conde_worlds.challenges import ChallengeError

    for i, challenge in enumerate(tournament.challenges):
        variants = []
        for variant in challenge.variants:
            try:
                _, name, _ = catalogue.select(challenge.name, variant or None, 0)
            except ChallengeError as error:
                raise TournamentError("%s: challenges[%d]: %s" % (tournament.path, i, error)) from error
            variants.append(name)
        tournament.challenges[i] = Challenge(challenge.name, tuple(variants), challenge.seeds)


def load_tournament(path: str, catalogue=None) -> Tournament:
    """Reads and validates a tournament file; TournamentError names the file and the key.
    catalogue: the challenges to check against (default conde_worlds' challenges.yaml)."""
    text = config_files.read_text(path, TournamentError, "the tournament file")
    data = config_files.parse_yaml(text, path, TournamentError, "not valid YAML")
    tournament = parse_tournament(data, path)
    if catalogue is None:
        from conde_worlds.challenges import load_challenges
        catalogue = load_challenges()
    check_challenges(tournament, catalogue)
    return tournament


def team_problem(team: Team) -> Optional[str]:
    """Why this team's jobs cannot start (a missing file), or None."""
    for what, path in (("launch", team.launch), ("overlay", team.overlay), ("lockstep_config", team.lockstep_config)):
        if path and not os.path.isfile(path):
            return "team %s: %s file %s does not exist" % (team.name, what, path)
    return None
