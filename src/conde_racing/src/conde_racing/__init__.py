"""F1/10-style racing in conde_sim: racetrack geometry, lap timing, a reference driver, teleop."""
