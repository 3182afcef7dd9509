"""Suite-wide settings: hypothesis runs derandomised so every CI run draws the same examples; the real
rcssserver fixtures (tests/rcss/real_server.py) are available to every test."""

from hypothesis import settings

from tests.rcss.real_server import rcssserver, start_servers  # noqa: F401  (fixtures)

settings.register_profile("soccer-lab", derandomize=True, deadline=None, max_examples=150)
settings.load_profile("soccer-lab")
