"""The matches study (`soccer-lab experiment matches`, docs/research/matches.md): players evolved alone (the chapter's setting),
co-evolved against a hall of fame of earlier bests, and co-evolved seeing the opponent, put on one pitch.

Its trials (app/experiment/presets.py): `alone` is Table 2 as the `initial` preset runs it; the co-evolved
settings run Table 2 with each evaluation a match against each of the hall's members drawn (HallEvaluator,
ga/hall_of_fame.py), the hall founded by the built-in demo. Every generation of a co-evolved trial also
re-plays CROWD_PLAYERS of its players (spread evenly over the population's order, so a sample of it, not
its best) against the generation's opponents and counts the ticks both players are within CROWD_DISTANCE
of the ball: the share of "kiddie soccer", kept in the trial's best.json by generation.

The questions, answered at report time from the trials' best players (trials/*.best.json), by matches played
then (each from seeds derived from the player's trial seed: the same folder gives the same answers):
(a) does a player evolved alone beat the built-in demo? Each alone trial's best plays DEMO_MATCHES matches
    against the demo; per trial, the mean goal difference per match.
(b) does a co-evolved player beat the chapter's best? Each co-evolved trial's best plays PAIR_MATCHES
    matches against each alone trial's best; per co-evolved trial, the mean goal difference per match.
(c) does kiddie soccer appear and pass? Per co-evolved trial (both co-evolved settings), the crowd share's
    mean over the first, middle and last third of the generations: it appears when the middle third's is
    above the first's, passes when the last third's is below the middle's.
(d) does seeing the opponent help? Each seeing trial's best plays PAIR_MATCHES matches against each
    co-evolved (not seeing) trial's best; per seeing trial, the mean goal difference per match.
(a), (b), (d): Wilcoxon signed-rank, two-sided, of the per-trial mean goal differences against 0; (c):
Wilcoxon signed-rank, one-sided, paired by trial. Each "no significant difference" says the smallest shift its
test could have detected (normal approximation, the trials counted at the rank test's efficiency).
"""

from __future__ import annotations

import json
import textwrap
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Sequence

import numpy as np
from matplotlib.figure import Figure as MatplotlibFigure
from matplotlib.ticker import MaxNLocator
from scipy import stats

from soccer_lab.app.experiment.figures import DPI, FIGURES_FOLDER, SIZE_INCHES, TITLE_CHARACTERS, Figure
from soccer_lab.app.experiment.presets import ALONE, COEVOLVED, MATCHES, SEEING, Preset
from soccer_lab.app.experiment.table import SEED, SETTING, TRIAL, BestsTable
from soccer_lab.app.experiment.verdicts import ALPHA, NOT_RUN, POWER, RANK_EFFICIENCY, Assessment
from soccer_lab.soccer.match import CROWD_DISTANCE

MATCHES_INTRODUCTION = (
    "Not the chapter's future work but its background's next step (Luke's co-evolved teams): players evolved alone (Table 2, the "
    "chapter's setting), co-evolved against a hall of fame of earlier bests founded by the built-in demo, and "
    "co-evolved seeing the opponent, put on one pitch. A co-evolved run's fitness is over matches against its hall, "
    "not comparable with a run's alone; its best is re-played against the demo. The questions are answered by "
    "matches between the trials' bests played when this report was written, and the co-evolved runs' share of "
    "ticks both players are near the ball by generation (kiddie soccer).")
CROWD_PLAYERS = 10  # players of each co-evolved generation re-played against its opponents for the crowd share
DEMO_MATCHES = 20  # matches each alone trial's best plays against the demo
PAIR_MATCHES = 4  # matches between two trials' bests
MATCHES_KEY = 0x6D61746368  # "match": the head-to-head seeds' branch of a trial's seed
DEMO_LABEL = "the built-in demo"
NO_DIFFERENCE = "no significant difference"
TRIALS_FOLDER = "trials"  # app/experiment/runner.py's, where each trial's best.json lies


# ---- the co-evolved trials -----------------------------------------------------------------------------
class CrowdMeter:
    """GA callback: after each generation, the share of ticks both players were near the ball in matches of
    CROWD_PLAYERS of its players against the generation's opponents (each from the player's first seed). With
    a `path`, the shares so far are kept there after each generation (a checkpointed trial resumes with them,
    `resumed`)."""

    def __init__(self, game: Any, vocabulary: Any, path: Path | None = None, generations: int = 0):
        from soccer_lab.ga.codec import ChromosomeCodec

        self.game, self.vocabulary, self.codec = game, vocabulary, ChromosomeCodec(vocabulary)
        self.opponents: list[Any] = []
        self.path = path
        kept = json.loads(path.read_text()) if path is not None and path.is_file() else []
        self.shares: list[float] = (kept + [float("nan")] * generations)[:generations]

    def on_opponents(self, generation: int, members: list[Any]) -> None:
        self.opponents = [self.codec.decode(member.chromosome) for member in members]

    def resumed(self, state: Any) -> None:
        """Continue after a checkpoint's `state`: the last generation's share, when a kill between the checkpoint
        and the file lost it, measured again from the checkpoint's population and opponents."""
        if self.shares and np.isnan(self.shares[-1]):
            self.on_opponents(len(self.shares) - 1, list(state.hall.drawn))
            self.shares[-1] = self.share(state.population)
            self._keep()

    def on_generation(self, stats: Any, population: list[Any]) -> None:
        self.shares.append(self.share(population))
        self._keep()

    def _keep(self) -> None:
        if self.path is not None:
            temporary = self.path.with_name(self.path.name + ".tmp")
            temporary.write_text(json.dumps(self.shares))
            temporary.replace(self.path)

    def share(self, population: list[Any]) -> float:
        from soccer_lab.soccer.match import MatchBatch

        step = max(1, len(population) // CROWD_PLAYERS)
        players = [(self.codec.decode(i.chromosome), i.first_seed or 0) for i in population[::step][:CROWD_PLAYERS]]
        pairs, seeds = [], []
        for rulebase, seed in players:
            if len(rulebase):
                for opponent in self.opponents:
                    pairs += [(rulebase, opponent), (opponent, rulebase)]
                    seeds += [seed, seed]
        halves = MatchBatch(pairs, seeds, self.game, self.vocabulary).run() if pairs else []
        ticks = sum(h.ticks for h in halves)
        return sum(h.crowded for h in halves) / ticks if ticks else 0.0


def run_coevolution_trial(spec: Any) -> Any:
    """A co-evolved trial of the matches preset: Table 2 against a hall of fame founded by the built-in demo, its
    crowd share by generation, its best re-played in one match against the demo from each replay start. With
    the spec's checkpoint, checkpointed after every generation, and continued from it when it is there."""
    from soccer_lab.app.experiment.trial_result import TrialResult, best_record, crowd_file
    from soccer_lab.fuzzy.vocabulary import Vocabulary
    from soccer_lab.ga.algorithms import evolve, resume
    from soccer_lab.ga.checkpoint import load_checkpoint
    from soccer_lab.ga.codec import ChromosomeCodec
    from soccer_lab.ga.hall_of_fame import founded_hall
    from soccer_lab.soccer.config import SOCCER_VOCABULARY
    from soccer_lab.soccer.match import HallEvaluator, MatchEvaluator

    setting = spec.setting
    vocabulary = Vocabulary.with_opponent() if setting.see_opponent else SOCCER_VOCABULARY
    demo = _demo()
    hall = founded_hall(ChromosomeCodec(vocabulary).encode(demo), DEMO_LABEL, setting.coevolve.hall_size,
                        setting.coevolve.hall_sample)
    evaluate = HallEvaluator(config=spec.game, vocabulary=vocabulary)
    checkpoint = spec.checkpoint
    if checkpoint is not None and checkpoint.is_file():
        state = load_checkpoint(checkpoint)
        meter = CrowdMeter(spec.game, vocabulary, crowd_file(checkpoint), len(state.history))
        meter.resumed(state)
        result = resume(checkpoint, evaluate, callbacks=[meter])
    else:
        meter = CrowdMeter(spec.game, vocabulary, crowd_file(checkpoint) if checkpoint is not None else None)
        result = evolve(spec.config, evaluate, vocabulary, hall=hall, callbacks=[meter], checkpoint=checkpoint)
    rows = [stats.to_dict() for stats in result.history]
    replay = MatchEvaluator(demo, spec.game.model_copy(update={"games_per_evaluation": 1}), vocabulary)
    best = best_record(result, rows, replay, spec.replay_seeds())
    return TrialResult(rows, {**best, "crowd_share": meter.shares, "see_opponent": setting.see_opponent,
                              "game": spec.game.model_dump()})


def _demo() -> Any:
    from soccer_lab.soccer.config import SOCCER_VOCABULARY
    from soccer_lab.soccer.examples import example

    return example("demo").rulebase(SOCCER_VOCABULARY)


# ---- the study, from the trials' bests ------------------------------------------------------------------
@dataclass(frozen=True)
class Player:
    setting: str
    trial: int
    seed: int
    rulebase: Any
    crowd_share: list[float]


@dataclass(frozen=True)
class MatchesStudy:
    """The questions' data: per trial, mean goal difference per match against the demo (alone), against the
    alone bests (co-evolved), against the co-evolved bests (seeing); the co-evolved trials' crowd shares."""

    against_demo: np.ndarray
    coevolved_against_alone: np.ndarray
    seeing_against_coevolved: np.ndarray
    crowd: dict[str, np.ndarray]  # setting -> trials x generations
    wins: dict[str, float]  # question -> share of its matches won by the player asked about

    @property
    def played(self) -> bool:
        return bool(len(self.against_demo) or len(self.coevolved_against_alone) or len(self.crowd))


def matches_study(folder: Path, preset: Preset, bests: BestsTable) -> MatchesStudy:
    """Plays the head-to-head matches between the trials' bests found in `folder` (none: an empty study)."""
    players = _players(folder, preset, bests)
    game = _game(folder, preset, bests)
    demo = _demo()
    alone, coevolved, seeing = (players.get(s, []) for s in (ALONE, COEVOLVED, SEEING))
    wins: dict[str, float] = {}
    against_demo = _goal_differences(alone, [demo], DEMO_MATCHES, game, "a", wins)
    coevolved_against_alone = _goal_differences(coevolved, [p.rulebase for p in alone], PAIR_MATCHES, game, "b", wins)
    seeing_against = _goal_differences(seeing, [p.rulebase for p in coevolved], PAIR_MATCHES, game, "d", wins)
    crowd = {s: _curves([p.crowd_share for p in players.get(s, [])]) for s in (COEVOLVED, SEEING) if players.get(s)}
    return MatchesStudy(against_demo, coevolved_against_alone, seeing_against, crowd, wins)


def _players(folder: Path, preset: Preset, bests: BestsTable) -> dict[str, list[Player]]:
    from soccer_lab.fuzzy.vocabulary import Vocabulary
    from soccer_lab.ga.codec import ChromosomeCodec
    from soccer_lab.ga.genes import GENE_DTYPE, GENE_WIDTH
    from soccer_lab.soccer.config import SOCCER_VOCABULARY

    found: dict[str, list[Player]] = {}
    for setting in preset.settings:
        codec = ChromosomeCodec(Vocabulary.with_opponent() if setting.see_opponent else SOCCER_VOCABULARY)
        for row in sorted((r for r in bests.rows if r["preset"] == MATCHES and r[SETTING] == setting.label),
                          key=lambda r: int(r[TRIAL])):
            path = folder / TRIALS_FOLDER / f"{setting.key}-{int(row[TRIAL])}.best.json"
            if not path.is_file():
                continue
            record = json.loads(path.read_text())
            chromosome = np.array(record["chromosome"], dtype=GENE_DTYPE).reshape(-1, GENE_WIDTH)
            found.setdefault(setting.label, []).append(Player(setting.label, int(row[TRIAL]), int(row[SEED]),
                                                              codec.decode(chromosome), record.get("crowd_share", [])))
    return found


def _game(folder: Path, preset: Preset, bests: BestsTable) -> Any:
    """The trials' game (a co-evolved trial keeps it in its best.json), else Table 2's at the preset's length."""
    from soccer_lab.soccer.config import GameConfig

    for setting in preset.settings:
        for row in bests.rows:
            path = folder / TRIALS_FOLDER / f"{setting.key}-{int(row[TRIAL])}.best.json"
            if setting.coevolve is not None and row[SETTING] == setting.label and path.is_file():
                game = json.loads(path.read_text()).get("game")
                if game:
                    return GameConfig(**game).model_copy(update={"games_per_evaluation": 1})
    return GameConfig(max_ticks=preset.size.max_ticks)


def match_seeds(trial_seed: int, count: int) -> list[int]:
    from soccer_lab.app.experiment.trial_result import derived_seeds

    return derived_seeds(trial_seed, MATCHES_KEY, count)


def _goal_differences(players: Sequence[Player], opponents: Sequence[Any], matches: int, game: Any, question: str,
                      wins: dict[str, float]) -> np.ndarray:
    """Per player, the mean goal difference per match (its goals minus the opponent's) over `matches` matches
    against each opponent, all in one batch; `wins[question]`: the share of those matches it won."""
    from soccer_lab.fuzzy.vocabulary import Vocabulary
    from soccer_lab.soccer.match import HALVES, MatchBatch

    if not players or not opponents:
        return np.array([])
    pairs, seeds = [], []
    for player in players:
        player_seeds = match_seeds(player.seed, matches * len(opponents))
        for j, opponent in enumerate(opponents):
            for seed in player_seeds[j * matches:(j + 1) * matches]:
                pairs += [(player.rulebase, opponent), (opponent, player.rulebase)]
                seeds += [seed] * HALVES
    halves = MatchBatch(pairs, seeds, game, Vocabulary.with_opponent()).run()  # a chapter player plays the same in it
    per_player = HALVES * matches * len(opponents)
    differences, won = [], 0
    for i in range(len(players)):
        mine = halves[i * per_player:(i + 1) * per_player]
        margins = [first.goals[0] + second.goals[1] - first.goals[1] - second.goals[0]
                   for first, second in zip(mine[::2], mine[1::2])]
        differences.append(float(np.mean(margins)))
        won += sum(margin > 0 for margin in margins)
    wins[question] = won / (len(players) * matches * len(opponents))
    return np.array(differences)


def _curves(shares: list[list[float]]) -> np.ndarray:
    length = max((len(s) for s in shares), default=0)
    curves = np.full((len(shares), length), np.nan)
    for i, share in enumerate(shares):
        curves[i, :len(share)] = share
    return curves


# ---- the answers ------------------------------------------------------------------------------------
def detectable_shift(values: np.ndarray) -> tuple[float, float]:
    """The smallest mean shift from 0 (in the values' units, and in standard deviations) that a two-sided
    signed-rank test on these trials could have detected with probability POWER at ALPHA."""
    z = stats.norm.ppf(1 - ALPHA / 2) + stats.norm.ppf(POWER)
    in_deviations = float(z / np.sqrt(len(values) * RANK_EFFICIENCY)) if len(values) else float("nan")
    deviation = float(np.std(values, ddof=1)) if len(values) > 1 else float("nan")
    return in_deviations * deviation, in_deviations


def _signed_rank(values: np.ndarray, alternative: str = "two-sided") -> float:
    if len(values) == 0 or np.all(values == 0):
        return 1.0
    with np.errstate(divide="ignore", invalid="ignore"):
        return float(stats.wilcoxon(values, alternative=alternative).pvalue)


def head_to_head(values: np.ndarray, player: str, opponent: str, won: float | None, matches: str) -> Assessment:
    """Whether `player` beats `opponent`: the per-trial mean goal differences against 0."""
    if len(values) == 0:
        return Assessment("-", NOT_RUN, "no trials' bests to play")
    p = _signed_rank(values)
    median = float(np.median(values))
    measured = (f"goal difference per match ({player} minus {opponent}), median over {len(values)} trials "
                f"{median:+.2f} (trials from {values.min():+.2f} to {values.max():+.2f}); {player} won "
                f"{won:.0%} of the matches ({matches})")
    test = f"Wilcoxon signed-rank, two-sided, of the per-trial mean goal differences against 0, p = {p:.3g}"
    if p < ALPHA:
        answer = f"yes: {player} beats {opponent}" if median > 0 else f"no: {opponent} beats {player}"
        reason = f"the median trial's {player} {'scores' if median > 0 else 'concedes'} {abs(median):.2f} more a match"
        return Assessment(measured, answer, test, reason=reason)
    shift, deviations = detectable_shift(values)
    return Assessment(measured, NO_DIFFERENCE, f"{test}; with {len(values)} trials it could have detected a mean "
                      f"goal difference of about {shift:.2f} a match ({deviations:.2f} standard deviations; alpha "
                      f"{ALPHA}, power {POWER})", no_difference_found=True,
                      reason=f"neither side wins reliably: the trials' mean goal differences straddle 0")


def kiddie_soccer(crowd: dict[str, np.ndarray]) -> Assessment:
    """Does the crowd share rise from the first third of the generations to the middle, then fall in the last?"""
    curves = [c for c in crowd.values() if c.size]
    if not curves:
        return Assessment("-", NOT_RUN, "no co-evolved trials")
    curves = np.concatenate(curves)
    if curves.shape[1] < 3:
        return Assessment(f"{curves.shape[1]} generations", NOT_RUN, "thirds of the run need 3 generations")
    thirds = [np.nanmean(part, axis=1) for part in np.array_split(curves, 3, axis=1)]
    first, middle, last = thirds
    p_appears = _signed_rank(middle - first, "greater")
    p_passes = _signed_rank(middle - last, "greater")
    appears, passes = p_appears < ALPHA, p_passes < ALPHA
    measured = (f"share of ticks both players are within {CROWD_DISTANCE:g} m of the ball, median over "
                f"{len(first)} co-evolved trials: first third of the generations {np.median(first):.1%}, middle "
                f"{np.median(middle):.1%}, last {np.median(last):.1%}")
    answer = ("appears and passes" if appears and passes else "appears, does not pass" if appears
              else "no rise: " + ("it falls" if passes else NO_DIFFERENCE))
    shift, deviations = detectable_shift(middle - first)
    test = (f"Wilcoxon signed-rank, one-sided, paired by trial: middle third above the first, p = {p_appears:.3g}; "
            f"last third below the middle, p = {p_passes:.3g}; with {len(first)} trials a rise of about "
            f"{shift:.1%} ({deviations:.2f} standard deviations) could have been detected (alpha {ALPHA}, power "
            f"{POWER})")
    reason = ("kiddie soccer, as Luke saw it, is a phase: " if appears and passes else "") + (
        f"the crowd share goes {np.median(first):.1%} -> {np.median(middle):.1%} -> {np.median(last):.1%}")
    return Assessment(measured, answer, test, reason=reason, no_difference_found=not appears and not passes)


# ---- figures ----------------------------------------------------------------------------------------------
def write_matches_figures(study: MatchesStudy, folder: Path) -> list[Figure]:
    (folder / FIGURES_FOLDER).mkdir(parents=True, exist_ok=True)
    figures = []
    if study.crowd:
        figures.append(_save(_crowd_figure(study), folder, "crowd_share",
                             f"Kiddie soccer: share of ticks both players are within {CROWD_DISTANCE:g} m of the "
                             "ball, by generation (co-evolved runs; thick: median over trials, faint: each trial)"))
    groups = {"(a) alone vs the demo": study.against_demo, "(b) co-evolved vs alone": study.coevolved_against_alone,
              "(d) seeing vs co-evolved": study.seeing_against_coevolved}
    if any(len(v) for v in groups.values()):
        figures.append(_save(_head_to_head_figure(groups), folder, "head_to_head",
                             "Head to head: each trial's best, mean goal difference per match"))
    return figures


def _save(figure: MatplotlibFigure, folder: Path, kind: str, caption: str) -> Figure:
    figure.suptitle(textwrap.fill(caption, TITLE_CHARACTERS, break_on_hyphens=False), fontsize=10)
    relative = Path(FIGURES_FOLDER) / f"{MATCHES}-{kind}.png"
    figure.savefig(folder / relative, metadata={"Software": None})
    return Figure(relative, caption)


def _crowd_figure(study: MatchesStudy) -> MatplotlibFigure:
    figure = MatplotlibFigure(figsize=SIZE_INCHES, dpi=DPI, layout="constrained")
    axes = figure.subplots()
    for (setting, curves), colour in zip(study.crowd.items(), ("#1976d2", "#e65100")):
        generations = np.arange(curves.shape[1])
        for curve in curves:
            axes.plot(generations, 100 * curve, color=colour, alpha=0.2, linewidth=0.8)
        axes.plot(generations, 100 * np.nanmedian(curves, axis=0), color=colour, linewidth=2,
                  label=setting.replace(", ", ",\n") + f"\n({len(curves)} trials)")
    axes.set_xlabel("generation")
    axes.set_ylabel("ticks both near the ball (%)")
    axes.xaxis.set_major_locator(MaxNLocator(integer=True))
    axes.set_ylim(bottom=0)
    axes.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    axes.grid(alpha=0.3)
    return figure


def _head_to_head_figure(groups: dict[str, np.ndarray]) -> MatplotlibFigure:
    figure = MatplotlibFigure(figsize=SIZE_INCHES, dpi=DPI, layout="constrained")
    axes = figure.subplots()
    rng = np.random.default_rng(0)  # the points' sideways jitter only
    for x, values in enumerate(groups.values()):
        if len(values):
            axes.scatter(x + rng.uniform(-0.12, 0.12, len(values)), values, s=22, color="#1976d2", alpha=0.8)
            axes.hlines(np.median(values), x - 0.25, x + 0.25, color="#c62828", linewidth=2)
    axes.axhline(0, color="grey", linewidth=0.8, linestyle="--")
    axes.set_xticks(range(len(groups)), list(groups), fontsize=8)
    axes.set_ylabel("goal difference per match (player asked about)")
    axes.grid(alpha=0.3, axis="y")
    return figure


# ---- the questions as the report asks them ---------------------------------------------------------------
QUESTION_TEXTS = (
    ("a", "Does a player evolved alone (the chapter's setting) beat the built-in demo in matches?"),
    ("b", "Does a co-evolved player beat the chapter's best (evolved alone) head to head?"),
    ("c", "Does \"kiddie soccer\" (both players at the ball) appear and pass in co-evolution?"),
    ("d", "Does seeing the opponent help: does a player co-evolved with the opponent vocabulary beat one without?"),
)


def matches_questions(folder: Path, preset: Preset, bests: BestsTable) -> tuple[tuple[Any, ...], MatchesStudy]:
    """The preset's questions as the report asks them (app/experiment/beyond.py's Question, each answering with
    the study's assessment), and the study: its matches played now."""
    from soccer_lab.app.experiment.beyond import Question

    study = matches_study(folder, preset, bests)
    answers = matches_answers(study)
    return tuple(Question(MATCHES, f"background ({letter})", text, lambda *_, a=answers[letter]: a)
                 for letter, text in QUESTION_TEXTS), study


def matches_answers(study: MatchesStudy) -> dict[str, Assessment]:
    return {
        "a": head_to_head(study.against_demo, "alone", "the demo", study.wins.get("a"),
                          f"{DEMO_MATCHES} per trial's best"),
        "b": head_to_head(study.coevolved_against_alone, "co-evolved", "alone", study.wins.get("b"),
                          f"{PAIR_MATCHES} against each alone trial's best"),
        "c": kiddie_soccer(study.crowd),
        "d": head_to_head(study.seeing_against_coevolved, "seeing", "co-evolved", study.wins.get("d"),
                          f"{PAIR_MATCHES} against each co-evolved trial's best"),
    }
