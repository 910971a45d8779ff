"""conde_testing: the plumbing that the node tests of the conde_sim Python packages share
(ros_harness: roscore, workspace environment, waiting, processes, topic logs; pseudo_terminal)."""
