"""Arrival orders of several topics at a node: each topic in order on its own connection, the
topics interleaved at random (test helper of the TimeOrder tests)."""
import random


def arrivals(topics, seed, skew_s=0.05):
    """One arrival order: each topic in order, the topics interleaved at random, none more than
    skew_s of simulated time ahead of the others."""
    rng, cursors, out = random.Random(seed), [0] * len(topics), []
    while any(c < len(s) for c, s in zip(cursors, topics)):
        ready = [i for i, s in enumerate(topics) if cursors[i] < len(s)]
        earliest = min(topics[i][cursors[i]][0] for i in ready)
        i = rng.choice([i for i in ready if topics[i][cursors[i]][0] <= earliest + skew_s])
        out.append(topics[i][cursors[i]])
        cursors[i] += 1
    return out
