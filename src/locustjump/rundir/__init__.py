"""The one module that knows the layout of run and reproduction directories.

A **run** (``locustjump train``)::

    DIR/config.toml      the resolved configuration (locustjump.rundir.config)
    DIR/metrics.csv      one row per generation
    DIR/checkpoint.npz   the optimizer's state after the last generation
    DIR/best.npz         the best genome so far
    DIR/fitness.png      best and mean fitness per generation
    DIR/stop.json        why the optimizer stopped before the budget, if it did
    DIR/frozen.npz       behaviours built on frozen runs (composed): their genomes
                         (``simple.npz`` in runs made before config format 2)
    DIR/archive.npz      a quality-diversity run (map-elites, cma-me): its
                         elites, one per cell of the descriptor grid
    DIR/archive.png      their fitness over the grid
    DIR/elites/cell-I-J/ ``evaluate``/``render --cell I,J`` (or ``--elite K``)
    DIR/eval/            ``locustjump evaluate``: trajectories, figures, metrics.json
    DIR/sweep/           extra evaluations a behaviour declares (getup's sweep)
    DIR/video.mp4        ``locustjump render``
    DIR/report.html      ``locustjump report``

A **rule-based run** (``locustjump rules``, a reproduction's ``rules/``):
``summary.json``, ``trajectory.csv``, ``trajectory.png``.

A **reproduction** (``locustjump reproduce``): ``reproduce.toml``,
``results.md``, ``report.html`` and one subdirectory per stage.

A **reproduction over several seeds** (``locustjump reproduce --seeds``):
``seeds.toml``, ``results.md`` and ``report.html`` across seeds, and one
reproduction per seed in ``seed-<s>/``, the same as ``reproduce --seed s``
writes alone.

Every file is written atomically (temporary file, fsync, rename), so a crash
leaves the previous complete version, and read without pickle (TOML, JSON,
CSV, ``.npz`` with ``allow_pickle=False``), bounded in size before it is
parsed (:mod:`.reads`) and checked before anything is written: arrays
(:mod:`.arrays`), ``metrics.csv`` (:mod:`.metrics`), the checkpoint
(:mod:`.checkpoint`). A command writes a directory holding its lock
(:mod:`.lock`, :mod:`.outputs`).
"""

from locustjump.rundir.archive import has_archive, read_archive, write_archive
from locustjump.rundir.checkpoint import (
    check_kept_best,
    read_checkpoint,
    write_checkpoint,
)
from locustjump.rundir.elites import Elite, load_elite
from locustjump.rundir.files import (
    append_line,
    atomic_path,
    atomic_write_bytes,
    atomic_write_text,
    save_npz,
    write_json,
    write_toml,
)
from locustjump.rundir.layout import *  # noqa: F403
from locustjump.rundir.layout import (
    derived_dir,
    elite_dir,
    eval_metrics_path,
    is_multiseed,
    is_reproduction,
    is_rules_run,
    is_run,
    seed_dir,
)
from locustjump.rundir.lock import InUse, check_not_in_use, in_use, locked
from locustjump.rundir.metrics import (
    generations_done,
    metrics_extra_columns,
    metrics_line,
    read_metrics,
    truncate_metrics,
)
from locustjump.rundir.outputs import (
    check_out_dir,
    deriving,
    made_dir,
    make_dir,
    output_dir,
    output_file,
    prepare_out_file,
    remove_made,
)
from locustjump.rundir.reads import (
    load_npz,
    open_regular,
    read_bytes,
    read_json,
    read_text,
    read_toml,
)
from locustjump.rundir.run import (
    BestGenome,
    FrozenGenomes,
    behaviour_of,
    frozen_of,
    frozen_setting,
    load_best,
    load_config,
    load_run,
    write_config,
)
from locustjump.rundir.trajectory import (
    TRAJECTORY_COLUMNS,
    trajectory_table,
    write_trajectory_csv,
)
