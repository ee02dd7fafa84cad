"""Numbers in the notebooks' prose against what their cells print (issue
34, point 23): the helpers of tests/test_notebook_prose.py (the committed
notebooks) and tests/test_notebooks.py (each re-executed notebook).

The prose of a notebook is its Markdown cells as written; what a cell
displays (``display(Markdown(...))`` generated from computed values, and
printed text) is computed by definition. Every number in the prose must
be one that some cell prints: the same value to the digits the prose
gives (0.5 stands for anything printed in [0.45, 0.55); sign ignored:
"within 0.54 %" is backed by "−0.54 %").

Not numbers in this sense, and skipped: code and file names in
backquotes, references (Fig. 4–9, Table 1, §2.1.1, equation numbers
(67), (110)/(111)), years, journal volumes given as such (CMAME 194),
digits that are part of a name or a formula (2D, R₁, φ_min, 2P, a²,
16/(3π), x''), and the exceptions a notebook lists in :data:`FORMULAS`
(constants of formulas written out in the prose)."""

import re

SUPERSCRIPT = str.maketrans("⁻⁰¹²³⁴⁵⁶⁷⁸⁹", "-0123456789")
_POWER = (r"(?<![\w.])(?:(?P<mantissa>\d+(?:\.\d+)?)\s*[·×]\s*)?"
          r"(?P<base>\d+)(?P<exponent>[⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+)(?![\w])")
_PLAIN = (r"(?<![\w.^/√±₀-₉])[-−+]?(?P<digits>\d+(?:\.\d+)?)"
          r"(?:[eE](?P<exp>[-+−]?\d+))?(?![\w/²³(′'])")
_OUTPUT = r"(?<![\w.])[-−+]?(\d+(?:\.\d+)?)(?:[eE]([-+−]?\d+))?"

#: Per notebook: prose strings that hold formula constants, not data
#: (removed before the numbers are read).
FORMULAS = {
    "table1_frictionless": [],
    "table2_friction": [],
    "verification": ["2√(PR/(πE*))", "2P/(πa)", "E/(1 − ν²)",
                     "a√(1 − Q/(f_c P))"],
    "three_d": ["(3PR/(4E*))^(1/3)", "3P/(2πa²)", "√(1 − r²/a²)",
                "E/(1 − ν²)", "16/(3π)", "(1 − (2/15)(a/R)²)",
                "R − √(R² − r²)", "r²/(2R)"],
    "two_bodies": ["2N_a − N_b", "2√(P R*/(π E*))", "2P/(πa)",
                   "1/R* = 1/R₁ + 1/R₂", "1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂",
                   "√(1 − x²/a²)", "∫x²p/∫p = a²/4", "a√(1 − Q/(f_c P))",
                   "√(1 − x²/c²)", "h²/12", "ψ_j = 2 − 3s",
                   "∫₀¹(2 − 3s)s² ds = −1/12", "(h_l³ + h_r³)/(12(h_l + h_r))",
                   "T⁻ᵀKT⁻¹", "T⁻¹", "3N_a − N_b − N_c", "(3PR*/(4E*))^⅓",
                   "3P/(2πa²)", "√(1 − r²/a²)", "a(1 − Q/(f_c P))^⅓"],
}


def _strip(text, formulas=()):
    """The prose without what is not a number (module docstring)."""
    for formula in formulas:
        text = text.replace(formula, " ")
    text = re.sub(r"`[^`]*`", " ", text)
    text = re.sub(r"\]\([^)]*\)", "]", text)  # link targets
    text = re.sub(r"\b(?:Fig|Figs|Table|Tables)\.?\s*\d+(?:\s*\([a-z, ]+\))?"
                  r"(?:\s*[–-]\s*\d+)?(?:\s*(?:,|and)\s*\d+"
                  r"(?:\s*[–-]\s*\d+)?)*", " ", text)
    text = re.sub(r"§\s*\d+(?:\.\d+)*(?:\s*[–-]\s*\d+(?:\.\d+)*)?", " ",
                  text)
    text = re.sub(r"\(\d+\)(?:/\(\d+\))?", " ", text)
    text = re.sub(r"\b(?:19|20)\d\d\b", " ", text)
    text = re.sub(r"\b(?:CMAME|IJNME)\s+\d+", " ", text)
    return text


def _digits(text):
    """The value of ``text`` and half a unit of its last digit."""
    decimals = len(text.split(".")[1]) if "." in text else 0
    return float(text), 0.5 * 10.0 ** -decimals


def prose_numbers(text, formulas=()):
    """[(token, value, half unit)] of the numbers in Markdown prose."""
    text = _strip(text, formulas)
    out = []

    def power(match):
        base = float(match["base"])
        exponent = int(match["exponent"].translate(SUPERSCRIPT))
        mantissa = float(match["mantissa"] or 1.0)
        value = mantissa * base ** exponent
        if match["mantissa"]:
            half = _digits(match["mantissa"])[1] * base ** exponent
        else:
            half = 0.0
        out.append((match[0], value, half))
        return " "

    text = re.sub(_POWER, power, text)
    for match in re.finditer(_PLAIN, text):
        value, half = _digits(match["digits"])
        exponent = match["exp"]
        if exponent:
            scale = 10.0 ** int(exponent.replace("−", "-"))
            value, half = value * scale, half * scale
        out.append((match[0], value, half))
    return out


def output_numbers(text):
    """Every number printed in ``text`` (absolute values)."""
    values = []
    for match in re.finditer(_OUTPUT, text):
        value = float(match[1])
        if match[2]:
            value *= 10.0 ** int(match[2].replace("−", "-"))
        values.append(value)
    return values


def cell_output_text(cell):
    """What a code cell shows as text: streams, Markdown, plain results."""
    parts = []
    for output in cell.get("outputs", []):
        if "text" in output:
            parts.append("".join(output["text"]))
        data = output.get("data", {})
        for kind in ("text/markdown", "text/plain"):
            if kind in data:
                parts.append("".join(data[kind]))
                break
    return "\n".join(parts)


def unbacked_numbers(notebook, name):
    """[(cell index, token)] of prose numbers that no cell prints."""
    printed = []
    for cell in notebook["cells"]:
        if cell["cell_type"] == "code":
            printed += output_numbers(cell_output_text(cell))
    printed = sorted(set(printed))
    missing = []
    for index, cell in enumerate(notebook["cells"]):
        if cell["cell_type"] != "markdown":
            continue
        source = "".join(cell["source"])
        for token, value, half in prose_numbers(source, FORMULAS.get(name,
                                                                     ())):
            value = abs(value)
            tolerance = half + 1e-12 * value
            if not any(abs(p - value) <= tolerance for p in printed):
                missing.append((index, token))
    return missing
