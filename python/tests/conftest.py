# The Hypothesis settings of the whole suite: bounded, seeded (derandomize: the same
# examples on every run and machine), no deadline (a debug build or a loaded machine
# must not fail a test), no example database written anywhere.
# RAYPROOF_PY_EXAMPLES scales the number of examples per test (default 100).
import os

from hypothesis import HealthCheck, settings

settings.register_profile(
    "rayproof",
    max_examples=int(os.environ.get("RAYPROOF_PY_EXAMPLES", "100")),
    deadline=None,
    derandomize=True,
    database=None,
    # a shared, loaded machine must not fail a test by its speed
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
)
settings.load_profile("rayproof")
