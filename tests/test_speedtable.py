"""Values kept per rotor speed (model/speedtable.py)."""

import numpy as np


def test_speed_table_returns_what_compute_gives_at_any_speeds_and_computes_each_once():
    """SpeedTable (model/speedtable.py): rows kept in computing order in room that doubles,
    looked up through the sorted speeds; every answer equals a direct evaluation, each speed is
    computed once, and the limit starts the table afresh."""
    from groundres.model.speedtable import SpeedTable

    def direct(speeds):
        return speeds[:, None] * np.arange(3.0), np.sin(speeds)[:, None, None] * np.ones((1, 2, 2))

    computed = []

    def compute(speeds, table):
        assert np.all(np.diff(speeds) > 0)  # (sorted, unique)
        assert table.speeds is None or not np.isin(speeds, table.speeds).any()
        computed.extend(speeds)
        return direct(speeds)

    table = SpeedTable(compute, limit=500)
    rng = np.random.default_rng(5)
    pool = rng.uniform(0, 100, 300)
    for _ in range(200):
        speeds = rng.choice(pool, size=rng.integers(1, 9))
        for got, want in zip(table(speeds), direct(speeds)):
            np.testing.assert_array_equal(got, want)
    assert len(computed) == len(set(computed)) <= 300
    np.testing.assert_array_equal(table.speeds, np.sort(np.unique(computed)))
    for got, want in zip(table.values, direct(table.speeds)):
        np.testing.assert_array_equal(got, want)
    table(np.linspace(200, 300, 450))  # (past the limit: afresh, with the new speeds only)
    assert len(table.speeds) == 450
