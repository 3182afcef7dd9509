import pytest

from ga.config import ConfigError, GAConfig


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


@pytest.mark.parametrize(
    ("values", "message"),
    [
        ({"population_size": 1}, "population_size: Input should be greater than or equal to 2 (got 1)"),
        ({"max_length": 1}, "max_length: Input should be greater than or equal to 2"),
        ({"mutation_rate": 1.5}, "mutation_rate: Input should be less than or equal to 1 (got 1.5)"),
        ({"crossover_probability": -0.1}, "crossover_probability: Input should be greater than or equal to 0"),
        ({"consequent_probability": 0}, "consequent_probability: Input should be greater than 0"),
        ({"crossover": "uniform"}, "crossover: Input should be 'one-point' or 'two-point' (got 'uniform')"),
        ({"selection": "rank"}, "selection: Input should be 'roulette', 'tournament' or 'elitist'"),
        ({"workers": 0}, "workers: Input should be greater than or equal to 1"),
        ({"seed": -1}, "seed: Input should be greater than or equal to 0"),
        ({"population_size": "many"}, "population_size: Input should be a valid integer"),
        ({"popsize": 10}, "popsize: Extra inputs are not permitted"),
        ({"selection": "elitist", "population_size": 4, "elite_fraction": 0.9},
         "elite_fraction leaves no room to breed"),
    ],
)
def test_out_of_range_values_give_one_clear_line(values, message):
    with pytest.raises(ConfigError) as error:
        GAConfig.from_values(values)
    assert message in str(error.value)
    assert "\n" not in str(error.value)


def test_several_problems_are_reported_together():
    with pytest.raises(ConfigError, match="population_size: .*; workers: "):
        GAConfig.from_values({"population_size": 0, "workers": 0})
