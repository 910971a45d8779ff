"""image_sets: one set per frame of the sign node's cameras, in camera order."""
import pytest

from conde_traffic_sign.image_sets import ImageSets


def test_one_camera_gives_each_image_alone():
    sets = ImageSets(1)
    assert sets.add(0, 10, "a") == [(0, "a")]
    assert sets.add(0, 20, "b") == [(0, "b")]
    assert sets.dropped == 0


def test_two_cameras_give_one_set_per_frame_in_camera_order_whichever_comes_first():
    sets = ImageSets(2)
    assert sets.add(0, 10, "top10") == [(0, "top10")]  # the rear camera has not delivered yet: nothing waits for it
    assert sets.add(1, 20, "rear20") is None  # now it has: the top camera's image of 20 is owed
    assert sets.add(0, 20, "top20") == [(0, "top20"), (1, "rear20")]
    assert sets.add(0, 30, "top30") is None
    assert sets.add(1, 30, "rear30") == [(0, "top30"), (1, "rear30")]
    assert sets.dropped == 0


def test_the_first_frame_of_a_camera_that_comes_after_the_others_is_dropped():
    sets = ImageSets(2)
    assert sets.add(0, 10, "top10") == [(0, "top10")]  # judged alone: the rear camera had not delivered
    assert sets.add(1, 10, "rear10") is None and sets.dropped == 1  # its frame was judged
    assert sets.add(1, 20, "rear20") is None
    assert sets.add(0, 20, "top20") == [(0, "top20"), (1, "rear20")]


def test_a_camera_behind_the_others_owes_the_newest_stamp():
    sets = ImageSets(2)
    sets.add(0, 10, "top10")
    sets.add(1, 10, "rear10")  # dropped: the frame of 10 was judged
    assert sets.add(0, 20, "top20") is None  # the rear camera has delivered: its image of 20 is owed
    assert sets.add(1, 20, "rear20") == [(0, "top20"), (1, "rear20")]
    assert sets.add(0, 30, "top30") is None and sets.add(0, 40, "top40") is None  # the rear camera is late
    assert sets.add(1, 30, "rear30") is None  # older than the newest top image: its camera's next one is owed
    assert sets.add(1, 40, "rear40") == [(0, "top40"), (1, "rear40")]
    assert sets.dropped == 3  # rear10, top30, rear30


def test_a_world_reset_starts_the_stamps_again():
    sets = ImageSets(1)
    sets.add(0, 1000, "late")
    assert sets.add(0, 10, "after reset") is None
    sets.restart()
    assert sets.add(0, 10, "after reset") == [(0, "after reset")]


def test_no_camera_is_refused():
    with pytest.raises(ValueError, match="camera_count"):
        ImageSets(0)
