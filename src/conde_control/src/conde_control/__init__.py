"""conde_control: the lane-following control law (pure) used by the conde_control node."""
