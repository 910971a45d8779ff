"""The tournament file: what it gives, and a named error for each kind of mistake."""
import os

import pytest
import yaml

from conde_tournament.tournament_file import (TournamentError, check_challenges, load_tournament, parse_tournament,
                                              team_problem)

GOOD = {
    "name": "class",
    "teams": [{"name": "reference"},
              {"name": "a", "launch": "a/control.launch", "replaces": ["control", "decision"]},
              {"name": "b", "overlay": "/ws/devel/setup.bash"}],
    "challenges": [{"name": "D1", "seeds": [0, 3]}, {"name": "D3", "variants": ["v1", "v2"]}],
    "engines": ["ode", "bullet"],
    "repeats": 2,
    "limits": {"sim_s": 60, "wall_s": 300},
}


def parse(data, path="/t/tour.yaml"):
    return parse_tournament(data, path)


def test_every_combination_is_a_job_with_a_stable_id():
    t = parse(GOOD)
    jobs = t.jobs()
    # 3 teams x (D1: 2 seeds + D3: 2 variants) x 2 engines x 2 repeats
    assert len(jobs) == 3 * 4 * 2 * 2
    assert len({j.job_id for j in jobs}) == len(jobs)
    assert jobs[0].job_id == "reference__D1_default_seed0__ode__r0"
    assert t.teams[1].launch == "/t/a/control.launch" and t.teams[1].replaces == ("control", "decision")
    assert t.teams[2].overlay == "/ws/devel/setup.bash"
    assert (t.sim_limit_s, t.wall_limit_s, t.cpus_per_job) == (60.0, 300.0, 1)


def test_defaults():
    t = parse({"teams": [{"name": "x"}], "challenges": [{"name": "D2"}]}, "/t/my_class.yaml")
    assert t.name == "my_class" and t.engines == ["ode"] and t.repeats == 1
    assert [j.job_id for j in t.jobs()] == ["x__D2_default_seed0__ode__r0"]


@pytest.mark.parametrize("change, message", [
    ({"engine": ["ode"]}, "/t/tour.yaml: unknown key 'engine'"),
    ({"engines": ["gazebo"]}, "/t/tour.yaml: engines: unknown engine 'gazebo'"),
    ({"teams": []}, "/t/tour.yaml: teams: expected a non-empty list"),
    ({"teams": [{"name": "a b"}]}, "/t/tour.yaml: teams[0].name: expected a name"),
    ({"teams": [{"name": "a"}, {"name": "a"}]}, "teams: the name 'a' is used twice"),
    ({"teams": [{"name": "a", "replaces": ["control"]}]}, "teams[0].replaces: the team replaces control but has no"),
    ({"teams": [{"name": "a", "launch": "x.launch", "replaces": ["brain"]}]}, "teams[0].replaces: expected a list of"),
    ({"teams": [{"name": "a", "colour": "red"}]}, "teams[0]: unknown key 'colour'"),
    ({"challenges": [{"name": "D1", "seeds": [-1]}]}, "challenges[0].seeds: expected an integer >= 0, got -1"),
    ({"challenges": [{"seeds": [1]}]}, "challenges[0]: missing key 'name'"),
    ({"repeats": 0}, "repeats: expected an integer >= 1, got 0"),
    ({"limits": {"sim": 3}}, "limits: unknown key 'sim'"),
    ({"limits": {"wall_s": "long"}}, "limits.wall_s: expected a number >= 1, got 'long'"),
])
def test_errors_name_the_file_and_the_key(change, message):
    with pytest.raises(TournamentError) as error:
        parse(dict(GOOD, **change))
    assert message in str(error.value)


def test_missing_keys_and_bad_documents():
    with pytest.raises(TournamentError, match="missing key 'challenges'"):
        parse({"teams": [{"name": "a"}]})
    with pytest.raises(TournamentError, match="expected a mapping"):
        parse(["teams"])


def test_load_checks_yaml_and_challenges(tmp_path):
    path = tmp_path / "t.yaml"
    path.write_text("teams: [{name: a}\n")
    with pytest.raises(TournamentError, match="%s:2: not valid YAML" % path):
        load_tournament(str(path))
    with pytest.raises(TournamentError, match="cannot read"):
        load_tournament(str(tmp_path / "none.yaml"))
    path.write_text(yaml.safe_dump({"teams": [{"name": "a"}], "challenges": [{"name": "D1"}, {"name": "Z9"}]}))
    with pytest.raises(TournamentError, match=r"t.yaml: challenges\[1\]: .*unknown challenge 'Z9'"):
        load_tournament(str(path))
    path.write_text(yaml.safe_dump({"teams": [{"name": "a"}], "challenges": [{"name": "D1", "variants": ["v9"]}]}))
    with pytest.raises(TournamentError, match=r"challenges\[0\]: .*unknown variant 'v9'"):
        load_tournament(str(path))


def test_default_variant_is_named_from_the_catalogue():
    class Catalogue:
        def select(self, challenge, variant, seed):
            return None, variant or "first", seed

    t = parse({"teams": [{"name": "a"}], "challenges": [{"name": "D1"}]})
    check_challenges(t, Catalogue())
    assert [j.job_id for j in t.jobs()] == ["a__D1_first_seed0__ode__r0"]


def test_team_problem_names_the_missing_file(tmp_path):
    launch = tmp_path / "team.launch"
    t = parse({"teams": [{"name": "a", "launch": str(launch), "replaces": ["control"]}],
               "challenges": [{"name": "D1"}]})
    assert team_problem(t.teams[0]) == "team a: launch file %s does not exist" % launch
    launch.write_text("<launch/>")
    assert team_problem(t.teams[0]) is None
    assert os.path.isabs(t.teams[0].launch)
