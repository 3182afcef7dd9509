"""app/web/validation.py: pydantic's errors as one line for a person, as the CLI, the API and the UI show them."""

from __future__ import annotations

import pytest
from pydantic import ValidationError

from soccer_lab.app.web.validation import describe_problems
from soccer_lab.ga.config import GAConfig


def problems(values: dict, **options) -> str:
    with pytest.raises(ValidationError) as error:
        GAConfig(**values)
    return describe_problems(error.value.errors(), **options)


@pytest.mark.parametrize(
    ("values", "message"),
    [
        ({"population_size": 1}, "population_size: Input should be greater than or equal to 2 (got 1)"),
        ({"max_length": 1}, "max_length: Input should be greater than or equal to 2"),
        ({"mutation_rate": 1.5}, "mutation_rate: Input should be less than or equal to 1 (got 1.5)"),
        ({"crossover_probability": -0.1}, "crossover_probability: Input should be greater than or equal to 0"),
        ({"consequent_probability": 0}, "consequent_probability: Input should be greater than 0"),
        ({"crossover": "three-point"},
         "crossover: Input should be 'one-point', 'two-point' or 'uniform' (got 'three-point')"),
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
    described = problems(values)
    assert message in described and "\n" not in described


def test_several_problems_are_reported_together_and_places_named_by_the_caller():
    assert "population_size: " in problems({"population_size": 0, "workers": 0}).split("; ")[0]
    described = problems({"population_size": 0, "workers": 0}, where=lambda location: f"--{location[0]}")
    assert described.startswith("--population_size: Input should be greater than or equal to 2 (got 0); --workers: ")
