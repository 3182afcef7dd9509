"""Suite-wide settings: hypothesis runs derandomised so every CI run draws the same examples."""

from hypothesis import settings

settings.register_profile("soccer-lab", derandomize=True, deadline=None, max_examples=150)
settings.load_profile("soccer-lab")
