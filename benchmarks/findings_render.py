"""The blocks of docs/findings.md, rendered from the numbers benchmarks/findings_tables.py stores (no sesp:
the test that guards the page renders them too)."""

import math
import re


def finite(value):
    """``value`` with every non-finite float replaced by None (JSON has no NaN)."""
    if isinstance(value, dict):
        return {k: finite(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [finite(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _depth(c) -> str:
    return f"{c['depth']:.3g}–{c['top']:.3g} b"


def _box(c) -> str:
    x0, x1, y0, y1 = c["box"]
    return f"x {x0:+.3f}..{x1:+.3f}, y {y0:+.3f}..{y1:+.3f} b"


def n4_openings(stored) -> str:
    lines = [
        "| Ψ | count | components: certified depth (lower–upper bound), where | cells |",
        "|---|---|---|---|",
    ]
    for row in stored["rows"]:
        parts = [f"{_depth(c)}, {_box(c)}{'' if c['counted'] else ' (not counted)'}" for c in row["components"]]
        count = row["count"] if row["count"] is not None else f"{row['count_low']}–{row['count_high']}"
        lines.append(f"| {row['opening_deg']}° | {count} | {'; '.join(parts) or 'none'} | {row['cells']:,} |")
    return "\n".join(lines)


def _change(t) -> str:
    before = "–".join(str(v) for v in dict.fromkeys(t["count_before"]))
    after = "–".join(str(v) for v in dict.fromkeys(t["count_after"]))
    steps = "; ".join(f"{s['what']} ({_step_depths(s)}, {_box(s)})" for s in t["steps"]) or t["what"].split("; ", 1)[-1]
    return f"| {t['low_deg']:.3f}–{t['high_deg']:.3f}° | {before} → {after} | {t['kind']} | {steps} |"


def _step_depths(s) -> str:
    said = [f"{v:.2g} b" if v is not None else "none" for v in (s["depth_before"], s["depth_after"])]
    return f"depth {said[0]} → {said[1]}"


WIDEST_END_BAR = 10.0  # deg: an end estimate with a wider bar says nothing about where the component ends


def _life(k, life) -> str:
    depths = [d["depth"] for d in life["depths"]]
    said = f"{k}. listed {life['began_deg']:.3f}°–{life['ended_deg']:.3f}°, depth up to {max(depths):.3g} b"
    error = life["end_estimate_error_deg"]
    if life["end_estimate_deg"] is not None and error is not None and error > WIDEST_END_BAR:
        said += f", where it reaches 0 not estimated (its listed depths leave a bar of ±{error:.0f}°)"
    elif life["end_estimate_deg"] is not None:
        said += (f", its depth reaching 0 at {life['end_estimate_deg']:.2f}° ± {life['end_estimate_error_deg']:.2f}° "
                 f"(depth ≈ c·(end − Ψ)^{life['end_exponent']:.2f})")  # fmt: skip
    return said


def transitions(stored) -> str:
    lines = []
    for n, table in stored["tables"].items():
        lines += [f"**n = {n}** ({len(table['counts'])} openings counted):", "",
                  "| bracket | count | kind | what |", "|---|---|---|---|"]  # fmt: skip
        lines += [_change(t) for t in table["transitions"]]
        lines += ["", "Components followed over Ψ:", ""]
        lines += [_life(k, life) for k, life in enumerate(table["components"], 1)]
        lines.append("")
    return "\n".join(lines).rstrip()


BLOCKS = {"n4_openings": n4_openings, "transitions": transitions}


def render(page: str, stored: dict) -> str:
    """``page`` with each block ``<!-- findings:NAME -->`` ... ``<!-- /findings:NAME -->`` rendered from
    ``stored[NAME]`` (blocks without stored numbers are left as they are)."""
    for name, make in BLOCKS.items():
        if name not in stored:
            continue
        pattern = re.compile(rf"(<!-- findings:{name} -->\n)(?:.*?\n)?(<!-- /findings:{name} -->)", re.S)
        text = make(stored[name])
        page = pattern.sub(lambda m, text=text: m.group(1) + text + "\n" + m.group(2), page)
    return page
