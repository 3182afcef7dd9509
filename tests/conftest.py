"""Suite-wide settings: hypothesis runs derandomised so every CI run draws the same examples; the real
rcssserver fixtures (tests/rcss/real_server.py) are available to every test."""

import sys
from pathlib import Path

import pytest
from hypothesis import settings

from tests.rcss.real_server import rcssserver, start_servers  # noqa: F401  (fixtures)

settings.register_profile("soccer-lab", derandomize=True, deadline=None, max_examples=150)
settings.load_profile("soccer-lab")

# The docs hooks import their shared helpers (docs/hooks/markdown_table.py) as mkdocs lets them: with their
# folder on sys.path. Tests load the hooks from their files, so the folder is put there for them too.
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "docs" / "hooks"))


@pytest.fixture(scope="session")
def evolved_rulebases():
    """The last generation of a short, seeded GA run in SimpleSoccer: what evolution really produces
    (long messy antecedents, repeated and contradictory premises), kept small for speed."""
    from soccer_lab.ga import GAConfig, evolve
    from soccer_lab.ga.codec import ChromosomeCodec
    from soccer_lab.soccer.config import SOCCER_VOCABULARY, GameConfig
    from soccer_lab.soccer.evaluate import SimpleSoccerEvaluator

    result = evolve(GAConfig(population_size=16, max_generations=3, seed=11),
                    SimpleSoccerEvaluator(GameConfig(max_ticks=200)), SOCCER_VOCABULARY)
    codec = ChromosomeCodec(result.vocabulary)
    rulebases = [codec.decode(i.chromosome) for i in result.population]
    return [result.best_rulebase] + [r for r in rulebases if len(r)]


@pytest.fixture(scope="session")
def installed_wheel(tmp_path_factory):
    """This checkout as a user installs it: the wheel, in a folder of its own (tests/wheel_install.py)."""
    from tests.wheel_install import install

    return install(tmp_path_factory.mktemp("wheel"))
