"""Write docs/tutorial.ipynb from the cells below (unexecuted: outputs come
from running it). Edit the cells here, rerun, commit both files:

    python scripts/make_tutorial.py

tests/test_tutorial.py executes the notebook on a small budget and checks that
this script and the notebook agree.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path

import nbformat

NOTEBOOK = Path(__file__).resolve().parent.parent / "docs" / "tutorial.ipynb"

# one tuple a cell, the cell's text flush left as it will read
# fmt: off
CELLS: list[tuple[str, str]] = [
    ("md", """\
# Tutorial: evolve a kick, watch it, compose it

This notebook walks through locustjump's Python API in five steps:

1. train a small **kick** (the paper's first simple behaviour) with the RCGA,
2. plot its **learning curve** from the run directory's `metrics.csv`,
3. **watch** a frame of the jump (offscreen MuJoCo rendering),
4. **compose**: train the switching network over the paper's shipped simple
   behaviours (`results/paper-seed0`),
5. use the kick as a **Gymnasium** environment.

Run it from a clone after `make test` (or `pip install -e '.[video,gym]'`:
`make demo` installs no Gymnasium, which step 5 needs),
with Jupyter installed in that environment (`pip install jupyterlab`), from the
`docs/` folder or the repository root. The budget below is small on purpose
(about a minute on two cores); raise `GENERATIONS` for a kick that jumps like
the paper's (`results/paper-seed0/kick`: 1000 generations)."""),
    ("code", """\
import os
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

import locustjump as lj

# the suite runs this notebook with tiny values (tests/test_tutorial.py)
GENERATIONS = int(os.environ.get("LJ_TUTORIAL_GENERATIONS", "40"))
POPULATION = int(os.environ.get("LJ_TUTORIAL_POPULATION", "30"))

# the repository root (this notebook lives in docs/)
REPO = Path.cwd() if (Path.cwd() / "results").is_dir() else Path.cwd().parent
SHIPPED = REPO / "results" / "paper-seed0"  # the paper's budget, seed 0
WORK = Path(tempfile.mkdtemp(prefix="locustjump-tutorial-"))
print("runs go to", WORK)"""),
    ("md", """\
## 1. Train a kick

A run is a directory: `config.toml` (everything that determines the result),
`metrics.csv` (one row per generation), `best.npz` (the best genome) and an
atomic checkpoint. Same seed, same genomes, bit for bit, on any number of
threads."""),
    ("code", """\
cfg = lj.TrainConfig(
    behaviour="kick",
    seed=0,
    generations=GENERATIONS,
    optimizer=lj.RCGAParams(population=POPULATION),
)
kick = lj.train(cfg, WORK / "kick", progress=False)
print(f"best fitness {kick.best.fitness:.4f} after {kick.generation} generations "
      f"({kick.wall_s:.1f} s)")
print(sorted(p.name for p in kick.out.iterdir()))"""),
    ("md", """\
## 2. Its learning curve

`metrics.csv` reads as a NumPy structured array; the shipped 1000-generation
kick is drawn beside ours."""),
    ("code", """\
from locustjump.rundir.metrics import read_metrics

ours = read_metrics(kick.out / "metrics.csv")
paper = read_metrics(SHIPPED / "kick" / "metrics.csv")
fig, ax = plt.subplots(figsize=(6, 3.5))
ax.plot(paper["generation"], paper["best"], color="0.6", label="shipped (1000 gen.)")
ax.plot(ours["generation"], ours["best"], label=f"ours ({GENERATIONS} gen.)")
ax.plot(ours["generation"], ours["mean"], ":", label="ours, population mean")
ax.set(xlabel="generation", ylabel="kick fitness (Eq. 1, m$^2$)", xscale="log")
ax.legend()
plt.show()"""),
    ("md", """\
## 3. Watch it

`evaluate_run` re-simulates the best genome (its fitness must equal the
recorded one: the run replays bit for bit) and writes trajectory CSVs and
figures; `playback_of` + `frames` render the episode offscreen.
`locustjump render RUN --out kick.mp4` makes the video, `locustjump view RUN`
opens MuJoCo's viewer."""),
    ("code", """\
from itertools import islice

from locustjump.present.playback import playback_of
from locustjump.present.render import frames

ev = lj.evaluate_run(kick.out)
print(f"re-simulated fitness {ev.fitness:.6f}, recorded {ev.recorded_fitness:.6f}, "
      f"identical: {ev.matches}")

pb = playback_of(kick.out)
fps = 20
t_show = 1.0  # seconds into the episode
frame = next(islice(frames(pb, fps=fps), int(t_show * fps), None))
plt.figure(figsize=(6, 4.5))
plt.imshow(frame)
plt.axis("off")
plt.show()"""),
    ("md", """\
## 4. Compose with the shipped simple behaviours

The paper's successive jump is a switching network over three frozen
networks: kick, get-up and return-legs. Here they are the shipped runs of
`results/paper-seed0`; only the switcher evolves. (The 3000-step episode makes
a generation about ten times a kick's.)"""),
    ("code", """\
from locustjump.rundir import FrozenGenomes
from locustjump.tasks import behaviour_class

needs = behaviour_class("composed").requires
print("composed switches among", needs)
frozen = FrozenGenomes.from_runs(
    needs, {name: SHIPPED / name for name in needs}, lj.LocustParams()
)
ccfg = lj.TrainConfig(
    behaviour="composed",
    seed=0,
    generations=max(1, GENERATIONS // 10),
    optimizer=lj.RCGAParams(population=POPULATION),
)
composed = lj.train(ccfg, WORK / "composed", frozen=frozen, progress=False)
print(f"successive-jump fitness {composed.best.fitness:.1f} "
      f"(shipped, 1000 generations: see results/paper-seed0/results.md)")"""),
    ("md", """\
## 5. A Gymnasium environment

`import locustjump.envs` registers `LocustKick-v0`, `LocustGetUp-v0`,
`LocustReturnLegs-v0` and `LocustSuccessiveJump-v0` (needs the `gym` extra).
The return of an episode is the behaviour's fitness, so any RL or ES library
can be compared with the paper's RCGA on the same number."""),
    ("code", """\
import gymnasium as gym

import locustjump.envs  # noqa: F401  (registers the ids)

env = gym.make("LocustKick-v0")
obs, info = env.reset(seed=0)
env.action_space.seed(0)
ret, done = 0.0, False
while not done:
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    ret += reward
    done = terminated or truncated
env.close()
print(f"a random policy's kick return: {ret:.4f}; our evolved kick: "
      f"{kick.best.fitness:.4f}")"""),
    ("md", """\
## Where next

- The command line does all of this and more: `locustjump --help`; the
  whole paper in one command: `locustjump reproduce`.
- Compare optimizers (`--optimizer cma`), scenes (`--scene debris`) and
  seeds with a study file: `locustjump study studies/example.toml --dry-run`.
- Which of the paper's claims hold, and why: the science pages."""),
]
# fmt: on


def notebook() -> nbformat.NotebookNode:
    nb: nbformat.NotebookNode = nbformat.v4.new_notebook()
    nb.metadata["kernelspec"] = {
        "display_name": "Python 3",
        "language": "python",
        "name": "python3",
    }
    nb.metadata["language_info"] = {"name": "python"}
    make: dict[str, Callable[[str], nbformat.NotebookNode]] = {
        "md": nbformat.v4.new_markdown_cell,
        "code": nbformat.v4.new_code_cell,
    }
    nb.cells = [make[kind](src) for kind, src in CELLS]
    for i, cell in enumerate(nb.cells):
        cell["id"] = f"cell-{i}"  # stable ids: the file does not change on rerun
    return nb


def main(argv: list[str] | None = None) -> int:
    del argv
    nbformat.write(notebook(), NOTEBOOK)
    print(f"wrote {NOTEBOOK}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
