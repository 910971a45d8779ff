"""conde_common.config_files: the file and the line are named, with the caller's error type and words."""
import pytest
import yaml

from conde_common.config_files import parse_yaml, read_text


class Bad(ValueError):
    pass


def test_read_text(tmp_path):
    path = tmp_path / "a.yaml"
    path.write_text("steps: []\n")
    assert read_text(str(path), Bad, "the file") == "steps: []\n"


def test_missing_file_names_the_file_and_the_reason(tmp_path):
    path = str(tmp_path / "none.yaml")
    with pytest.raises(Bad) as info:
        read_text(path, Bad, "schedule")
    assert str(info.value) == f"{path}: cannot read schedule: No such file or directory"


def test_parse_yaml():
    assert parse_yaml("a: [1, 2]\n", "a.yaml", Bad, "malformed YAML") == {"a": [1, 2]}


def test_bad_yaml_names_the_line_and_the_problem():
    with pytest.raises(Bad) as info:
        parse_yaml("a: 1\nb: [1\n", "a.yaml", Bad, "invalid YAML")
    assert str(info.value) == "a.yaml:3: invalid YAML: expected ',' or ']', but got '<stream end>'"


def test_parse_yaml_with_the_callers_loader():
    class NoFloats(yaml.SafeLoader):  # a loader that refuses floats, with the node's position
        def construct_yaml_float(self, node):
            raise yaml.constructor.ConstructorError(None, None, "no floats here", node.start_mark)

    NoFloats.add_constructor("tag:yaml.org,2002:float", NoFloats.construct_yaml_float)
    assert parse_yaml("a: 1\n", "a.yaml", Bad, "bad", loader=NoFloats) == {"a": 1}
    with pytest.raises(Bad) as info:
        parse_yaml("a: 1\nb: 2.5\n", "a.yaml", Bad, "bad", loader=NoFloats)
    assert str(info.value) == "a.yaml:2: bad: no floats here"
