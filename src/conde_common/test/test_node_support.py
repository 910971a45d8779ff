"""The pure parts of conde_common.node_support: which private parameters are unknown, and the
message that names them."""
from conde_common.node_support import unknown_params_message, unknown_private_params

MASTER_PARAMS = ["/rosdistro", "/conde_control/config", "/conde_control/rate_hz", "/conde_control/rate_hzz",
                 "/conde_controller/x", "/conde_control/gains/p", "/conde_control/gains/i", "/use_sim_time"]


def test_only_the_nodes_own_unknown_first_level_names():
    assert unknown_private_params(MASTER_PARAMS, "/conde_control", ["config", "rate_hz"]) == \
        ["/conde_control/gains", "/conde_control/rate_hzz"]


def test_known_nested_parameters_pass():
    assert unknown_private_params(MASTER_PARAMS, "/conde_control", ["config", "rate_hz", "rate_hzz", "gains"]) == []


def test_namespaced_node():
    assert unknown_private_params(["/car0/lap_timer/cars", "/car0/lap_timer/car"], "/car0/lap_timer", ["cars"]) == \
        ["/car0/lap_timer/car"]


def test_message():
    assert unknown_params_message(["/n/a"], ["y", "x"]) == "unknown parameter /n/a (known: x, y)"
    assert unknown_params_message(["/n/a", "/n/b"], []) == "unknown parameters /n/a, /n/b (known: none)"
