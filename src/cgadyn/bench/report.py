"""Reporting for ``cgadyn bench``: the result of ``measure.benchmark`` as markdown tables
(also readable as plain text), a JSON file and a bar chart."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from .._json import dumps
from .measure import OPS, PARALLEL, TARGETS

__all__ = ["figure", "format_tables", "plot", "write_report"]

LIB_NAMES = {"cgadyn": "cgadyn", "pinocchio": "Pinocchio", "pygafro": "pygafro",
             "pinocchio_loop": "Pinocchio loop", "pinocchio_parallel": "Pinocchio InParallel"}


def _f(x: float | None, fmt: str = ".2f") -> str:
    return "—" if x is None else format(x, fmt)


def _met(ratio: float | None, limit: float) -> str:
    if ratio is None:
        return "—"
    return "yes" if ratio <= limit else "no"


def _single_table(res: dict) -> list[str]:
    g = "not installed" if res["pygafro"] == "not installed" else "n/a"
    lines = [
        f"### Single call from Python, µs per call ({res['robot']}, "
        f"{res.get('base', 'fixed')} base, nv = {res['nv']})", "",
        "| op | cgadyn | Pinocchio | pygafro | cgadyn/Pinocchio | target | met "
        "| cgadyn/pygafro | target | met |",
        "|---|---:|---:|---:|---:|---:|---|---:|---:|---|",
    ]
    for op in OPS:
        t, r = res["single_us"][op], res["ratios"]["single"][op]
        rp, rg = r.get("pinocchio"), r.get("pygafro")
        gt = _f(t.get("pygafro")) if t.get("pygafro") is not None else g
        tg = f"<= {TARGETS['fd_pygafro']:g}" if op == "aba" else ""
        mg = _met(rg, TARGETS["fd_pygafro"]) if op == "aba" else ""
        limit = TARGETS["single_pinocchio" if op in ("rnea", "aba", "crba")
                        else "single_derivatives"]
        lines.append(f"| {op} | {_f(t['cgadyn'])} | {_f(t['pinocchio'])} | {gt} | {_f(rp)} "
                     f"| <= {limit:g} | {_met(rp, limit)} | {_f(rg)} | {tg} | {mg} |")
    return lines


def _batch_table(res: dict) -> list[str]:
    thr, tl, tp = res["threads"], TARGETS["batch_loop"], TARGETS["batch_parallel"]
    lines = [
        f"### Batch throughput, µs per sample ({thr} threads for cgadyn and InParallel)", "",
        "| op | B | cgadyn | Pinocchio loop | Pinocchio InParallel | cgadyn/loop | target "
        "| cgadyn/InParallel | target |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for op in OPS:
        for b, ops in res["batch_us_per_sample"].items():
            t, r = ops[op], res["ratios"]["batch"][b][op]
            lines.append(
                f"| {op} | {b} | {_f(t['cgadyn'], '.3f')} | {_f(t.get('pinocchio_loop'), '.3f')} "
                f"| {_f(t.get('pinocchio_parallel'), '.3f')} | {_f(r.get('pinocchio_loop'))} "
                f"| <= {tl:g} | {_f(r.get('pinocchio_parallel'))} "
                f"| {'<= ' + format(tp, 'g') if op in PARALLEL else '—'} |")
    return lines


def _compute_table(res: dict) -> list[str]:
    nc = res["compute_batch"]
    lines = [
        f"### Where the time goes: compute per sample (batch of {nc} on 1 thread / {nc}) "
        "vs a single call", "",
        "| op | cgadyn compute | Pinocchio compute (InParallel, 1 thread) | cgadyn single call "
        "| cgadyn call overhead | cgadyn first call, single / batch (ms; compile or cache load) |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for op in OPS:
        c = res["compute_us_per_sample"][op]
        s = res["single_us"][op]["cgadyn"]
        fc = res["first_call_ms"][op]
        lines.append(f"| {op} | {_f(c['cgadyn'], '.3f')} | {_f(c.get('pinocchio_parallel'), '.3f')}"
                     f" | {_f(s)} | {_f(s - c['cgadyn'])} | {fc['single']:.1f} / "
                     f"{fc['batch']:.1f} |")
    return lines


def _target_table(res: dict) -> list[str]:
    lines = ["### The issue's targets (ratio cgadyn / other; below 1: cgadyn faster)", "",
             "| target | measured ratio | target | met |", "|---|---:|---:|---|"]
    for t in res["targets"]:
        met = "—" if t["met"] is None else ("yes" if t["met"] else "no")
        lines.append(f"| {t['what']} | {_f(t['ratio'])} | {t['target']} | {met} |")
    return lines


def format_tables(res: dict) -> str:
    """The result's tables as markdown (also readable as plain text)."""
    parts = [_single_table(res), _batch_table(res), _compute_table(res), _target_table(res)]
    return "\n\n".join("\n".join(p) for p in parts) + "\n"


def _machine_lines(res: dict) -> list[str]:
    m = res["machine"]
    return [
        "### Machine", "",
        f"- CPU: {m['cpu']}, {m['cores']} cores; threads for batches: {m['threads']}",
        f"- Python {m['python']}, numpy {m['numpy']}, numba {m['numba']}, "
        f"Pinocchio {m['pinocchio']}, cgadyn {m['cgadyn']}",
        f"- pygafro: {res['pygafro']}",
        f"- git commit: {m['commit']}",
        f"- date: {m['date']}; {m['platform']}; load average at the end: {m['load_average']}",
        f"- medians over {res['repeats']} repeats, libraries alternating case by case"
        + (" (quick mode)" if res["quick"] else ""),
    ]


def write_report(res: dict, outdir: str | Path, stem: str = "benchmark") -> list[Path]:
    """Write ``<stem>.md``, ``<stem>.json`` and ``<stem>.png`` into ``outdir``."""
    out = Path(outdir)
    out.mkdir(parents=True, exist_ok=True)
    md = out / f"{stem}.md"
    md.write_text(f"## cgadyn benchmark: {res['robot']}\n\n" + format_tables(res) + "\n"
                  + "\n".join(_machine_lines(res)) + "\n")
    js = out / f"{stem}.json"
    js.write_text(dumps(res, indent=1) + "\n")
    png = out / f"{stem}.png"
    plot(res, png)
    return [md, js, png]


def plot(res: dict, path: str | Path) -> None:
    """Bar chart (log scale): single-call µs and per-sample µs at the largest batch."""
    import matplotlib.pyplot as plt

    fig = figure(res)
    try:
        fig.savefig(path, dpi=100)
    finally:
        plt.close(fig)


def figure(res: dict):
    """The figure of :func:`plot`, on the Agg backend; the caller closes it."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    big = str(max(res["batches"]))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    _bars(axes[0], res["single_us"], ("cgadyn", "pinocchio", "pygafro"),
          f"single call, µs ({res['robot']})")
    _bars(axes[1], res["batch_us_per_sample"][big],
          ("cgadyn", "pinocchio_loop", "pinocchio_parallel"),
          f"batch {big}, µs per sample ({res['threads']} threads)")
    fig.tight_layout()
    return fig


TICK_LABELS = {"rnea_derivatives": "rnea deriv.", "aba_derivatives": "aba deriv.",
               "minverse": "M⁻¹"}
"""Short names under the bars: the full ones overlap their neighbours (the tables keep
them)."""


def _bars(ax, table: dict[str, dict[str, float]], libs: Sequence[str], title: str) -> None:
    width = 0.8 / len(libs)
    for k, lib in enumerate(libs):
        ys = [table[op].get(lib) for op in OPS]
        xs = [i + (k - (len(libs) - 1) / 2) * width for i in range(len(OPS))]
        pts = [(x, y) for x, y in zip(xs, ys, strict=True) if y is not None]
        if pts:
            ax.bar(*zip(*pts, strict=True), width=width, label=LIB_NAMES[lib])
    ax.set_xticks(range(len(OPS)), [TICK_LABELS.get(op, op) for op in OPS], rotation=30,
                  ha="right", rotation_mode="anchor")
    ax.set_yscale("log")
    ax.set_title(title)
    ax.legend()
    ax.grid(axis="y", which="both", alpha=0.3)


