"""conde_common.files: a file written under a temporary name appears whole, or not at all."""

import os

import pytest

from conde_common.files import replaced_whole


def test_the_file_appears_only_when_the_block_ends(tmp_path):
    target = tmp_path / "report.json"
    with replaced_whole(str(target)) as tmp:
        with open(tmp, "w") as f:
            f.write("{}\n")
        assert not target.exists()  # not yet: a watcher sees nothing half-written
        assert os.path.dirname(tmp) == str(tmp_path)  # same folder: the rename is one step
        assert tmp.endswith(".json")  # a writer that goes by the extension (savefig) still can
    assert target.read_text() == "{}\n"
    assert os.listdir(tmp_path) == ["report.json"]


def test_an_existing_file_is_replaced(tmp_path):
    target = tmp_path / "report.json"
    target.write_text("old")
    with replaced_whole(str(target)) as tmp:
        with open(tmp, "w") as f:
            f.write("new")
    assert target.read_text() == "new"


def test_a_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    target = tmp_path / "report.json"
    target.write_text("old")
    with pytest.raises(RuntimeError):
        with replaced_whole(str(target)) as tmp:
            with open(tmp, "w") as f:
                f.write("half")
            raise RuntimeError("the plot failed")
    assert target.read_text() == "old"
    assert os.listdir(tmp_path) == ["report.json"]
