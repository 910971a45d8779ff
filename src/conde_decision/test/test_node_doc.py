"""The node's documentation states the defaults the code uses: every "~name (value)" in the
docstring of scripts/conde_decision is the default of that DecisionConfig or AvoidanceConfig field."""
import os
import re

from conde_decision.avoidance import AvoidanceConfig
from conde_decision.decision_logic import DecisionConfig

SCRIPT = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "scripts", "conde_decision")


def test_documented_defaults_are_the_code_defaults():
    with open(SCRIPT) as f:
        doc = f.read().split('"""')[1]
    documented = dict(re.findall(r"~(\w+) \(([-\d.]+)\)", doc))
    assert documented, "no '~name (default)' in the node's docstring"
    for name, value in documented.items():
        config = next((c for c in (DecisionConfig(), AvoidanceConfig()) if hasattr(c, name)), None)
        assert config is not None, f"the docstring names ~{name}, which neither config has"
        assert float(value) == getattr(config, name), f"~{name}: documented {value}, code {getattr(config, name)}"
