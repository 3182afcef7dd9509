"""The scalar Mamdani engine: the readable reference the batched kernel is tested against."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Mapping

from soccer_lab.fuzzy.defuzzifier import mean_of_maximum
from soccer_lab.fuzzy.rule import OR, Premise, Rule, Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary


@dataclass(frozen=True)
class ActionOutput:
    """One fired action: its support (largest rule strength) and a value per output it uses."""

    action: str
    support: float
    parameters: dict[str, float]
    first_rule: int  # index of the first rule reaching the support (breaks ties)


@dataclass(frozen=True)
class Inference:
    premise_degrees: list[list[float]]  # per rule, per premise
    strengths: list[float]  # per rule
    fired: list[ActionOutput]  # in order of first firing rule
    selected: ActionOutput | None  # None: no rule fired, the player hunts
    clipped_sets: dict[str, dict[str, list[tuple[str, float]]]] = field(default_factory=dict)
    # action -> output -> [(term, clip level)] of the rules contributing to it (for the UI)

    @property
    def no_rule_fired(self) -> bool:
        return self.selected is None


class Engine:
    """Evaluates one rulebase on crisp inputs.

    `inputs` maps input names (ball_distance, ...) to crisp values; an object whose inputs
    are missing or None is not visible, and every premise about it has degree 0.
    """

    def __init__(self, rulebase: Rulebase, vocabulary: Vocabulary):
        self.rulebase = rulebase
        self.vocabulary = vocabulary

    def visible_objects(self, inputs: Mapping[str, float | None]) -> set[str]:
        return {
            obj
            for obj, kinds in self.vocabulary.objects.items()
            if all(inputs.get(name) is not None for name in kinds.values())
        }

    def premise_degree(self, premise: Premise, inputs: Mapping[str, float | None], visible: set[str]) -> float:
        if premise.object not in visible:
            return 0.0
        kind = self.vocabulary.premise_variable(premise.term)
        variable = self.vocabulary.variables[kind]
        x = variable.clamp(float(inputs[self.vocabulary.objects[premise.object][kind]]))
        degree = variable.term(premise.term).membership(x)
        return 1.0 - degree if premise.negated else degree

    @staticmethod
    def combine(rule: Rule, degrees: list[float]) -> float:
        """Strict left-to-right: AND = min, OR = max, no precedence."""
        strength = degrees[0]
        for connector, degree in zip(rule.connectors, degrees[1:]):
            strength = max(strength, degree) if connector == OR else min(strength, degree)
        return strength

    def infer(self, inputs: Mapping[str, float | None]) -> Inference:
        vocabulary = self.vocabulary
        visible = self.visible_objects(inputs)
        premise_degrees = [[self.premise_degree(p, inputs, visible) for p in rule.premises] for rule in self.rulebase]
        strengths = [self.combine(rule, d) for rule, d in zip(self.rulebase, premise_degrees)]

        support: dict[str, float] = {}
        first_rule: dict[str, int] = {}
        for index, (rule, strength) in enumerate(zip(self.rulebase, strengths)):
            action = rule.consequent.action
            if strength > 0.0 and strength > support.get(action, 0.0):
                support[action] = strength
                first_rule[action] = index

        fired: list[ActionOutput] = []
        clipped: dict[str, dict[str, list[tuple[str, float]]]] = {}
        for action in sorted(support, key=first_rule.__getitem__):
            parameters = {}
            clipped[action] = {}
            for output in vocabulary.actions[action]:
                sets = [
                    (getattr(rule.consequent, output), strength)
                    for rule, strength in zip(self.rulebase, strengths)
                    if rule.consequent.action == action and strength > 0.0 and getattr(rule.consequent, output)
                ]
                clipped[action][output] = sets
                parameters[output] = self.defuzzify(output, sets)
            fired.append(ActionOutput(action, support[action], parameters, first_rule[action]))

        selected = None
        for candidate in fired:  # ordered by first rule, so the first of equal supports wins
            if selected is None or candidate.support > selected.support:
                selected = candidate
        return Inference(premise_degrees, strengths, fired, selected, clipped)

    def defuzzify(self, output: str, sets: list[tuple[str, float]]) -> float:
        if not sets:
            return self.vocabulary.output_default(output)
        return mean_of_maximum(self.maximum_cuts(output, sets))

    def maximum_cuts(self, output: str, sets: list[tuple[str, float]]) -> list[tuple[float, float]]:
        """The intervals whose union is where the aggregate of the clipped `sets` reaches its maximum."""
        variable = self.vocabulary.output_variable(output)
        level = max(strength for _, strength in sets)
        return [variable.term(term).alpha_cut(level) for term, strength in sets if strength == level]
