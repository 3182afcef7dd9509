import pytest
from pydantic import ValidationError

from soccer_lab.ga.config import GAConfig


def test_defaults_are_the_chapters_table_2():
    config = GAConfig()
    assert (config.max_length, config.population_size, config.max_generations) == (64, 200, 25)
    assert (config.selection, config.crossover) == ("roulette", "one-point")
    assert (config.crossover_probability, config.mutation_rate, config.mutation_probability) == (0.8, 0.10, 0.35)
    assert (config.tournament_size, config.tournament_selector, config.elite_fraction) == (2, 0.75, 0.05)
    assert config.consequent_probability == 0.25 and config.target_fitness == 0.05


def test_config_is_frozen():
    with pytest.raises(Exception):
        GAConfig().seed = 3


def test_elite_count_is_five_percent_for_elitist_selection_only():
    assert GAConfig(selection="elitist").elite_count == 10
    assert GAConfig(selection="elitist", population_size=10).elite_count == 1  # at least one
    assert GAConfig().elite_count == 0


@pytest.mark.parametrize("values", [
    {"population_size": 1}, {"mutation_rate": 1.5}, {"crossover": "three-point"}, {"workers": 0}, {"popsize": 10},
    {"selection": "elitist", "population_size": 4, "elite_fraction": 0.9},
])
def test_out_of_range_values_are_refused(values):
    with pytest.raises(ValidationError):  # app/web/validation.py words it for people (tests/app/test_validation.py)
        GAConfig(**values)
