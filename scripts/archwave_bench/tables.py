"""Numbers and Markdown tables as the report prints them."""

import math
import re


def fmt(x, digits=3):
    """Significant digits, without scientific notation for ordinary magnitudes."""
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "–"
    if x == 0:
        return "0"
    if abs(x) >= 10 ** digits or abs(x) < 1e-3:
        return f"{x:.{digits - 1}e}"
    return f"{x:.{max(0, digits - 1 - int(math.floor(math.log10(abs(x)))))}f}"


def fmt_bytes(b):
    for unit, scale in (("GiB", 1 << 30), ("MiB", 1 << 20), ("KiB", 1 << 10)):
        if b >= scale:
            return f"{b / scale:.3g} {unit}"
    return f"{int(b)} B"


def _numeric(s):
    return re.fullmatch(r"[-+]?[\d.,]+(e[-+]?\d+)?[x%]?( [KMG]iB| B)?|–", str(s)) is not None


def md_table(headers, rows):
    """Markdown table; a column is right-aligned when every cell in it is a number."""
    align = ["---:" if rows and all(_numeric(r[i]) for r in rows) else "---" for i in range(len(headers))]
    out = ["| " + " | ".join(headers) + " |", "|" + "|".join(align) + "|"]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out) + "\n"


def rate(count, seconds):
    """Millions per second."""
    return fmt(count / seconds * 1e-6)


def ray_rate(stats, seconds):
    """Closest plus shadow rays, millions per second."""
    return rate(stats["closest_rays"] + stats["shadow_rays"], seconds)
