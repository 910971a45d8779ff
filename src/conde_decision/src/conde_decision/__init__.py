"""conde_decision: the YAML state machine and the decision logic (pure) of the conde_decision node."""
