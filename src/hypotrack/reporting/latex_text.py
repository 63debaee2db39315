r"""Generated prose in LaTeX: plain-text notation of the ledger typeset as mathematics.

The ledger (``claims.csv``) is plain text read by people, the README and the report alike, so its
notes write ``p_D``, ``<=``, ``1e+06``, ``±``, ``λ`` and ``N̂``. The README shows them as they are;
the report must not print ASCII mathematics. :func:`latex_text` escapes LaTeX's special characters
*and* sets these forms in math mode:

====================  ==========================================
plain text            LaTeX
====================  ==========================================
``<=  >=  !=  ->``    ``\le  \ge  \ne  \to``
``+/-``, ``±``        ``\pm``
``1e+06``, ``3.9e-22``  ``10^{6}``, ``3.9\times10^{-22}``
``p_D``, ``H_inf``    ``p_{D}``, ``H_{\infty}`` (one letter, a short subscript)
``p_D**3``, ``p_D³``  ``p_{D}^{3}``
Greek, ``≤ ≥ × · √ ∞ ≈``  their math symbols
``N̂``, ``x̄``          ``\hat{N}``, ``\bar{x}``
``n-hat``, ``Vbar``     ``\hat{n}``, ``\bar{V}``
``exp(-lambdaV)``     ``e^{-\lambda V}`` (``lambdaV`` alone: ``\lambda V``)
``sqrt``, ``oo``        ``\surd``, ``\infty``
``-3``, ``a - b``, ``−``  a minus sign (a hyphen before a digit or between spaces)
``1e4-1e5``            ``10^{4}--10^{5}`` (a range)
====================  ==========================================

Every other character is escaped by :func:`latex_escape`. A code name
such as ``rfisst_chain`` is left alone: only a single letter before ``_`` starts a subscript.
"""

from __future__ import annotations

import re

__all__ = ["ASCII_MATH", "latex_escape", "latex_text"]

_LATEX_SPECIAL = {"&": r"\&", "%": r"\%", "$": r"\$", "#": r"\#", "_": r"\_", "{": r"\{", "}": r"\}",
                  "~": r"\textasciitilde{}", "^": r"\textasciicircum{}", "\\": r"\textbackslash{}"}


def latex_escape(text) -> str:
    """Escape LaTeX's special characters in plain text (no other change)."""
    return "".join(_LATEX_SPECIAL.get(ch, ch) for ch in str(text))


_GREEK = {"α": r"\alpha", "β": r"\beta", "γ": r"\gamma", "δ": r"\delta", "ε": r"\varepsilon", "η": r"\eta",
          "θ": r"\theta", "κ": r"\kappa", "λ": r"\lambda", "μ": r"\mu", "ν": r"\nu", "ξ": r"\xi", "π": r"\pi",
          "ρ": r"\rho", "σ": r"\sigma", "τ": r"\tau", "φ": r"\phi", "χ": r"\chi", "ψ": r"\psi", "ω": r"\omega",
          "Γ": r"\Gamma", "Δ": r"\Delta", "Θ": r"\Theta", "Λ": r"\Lambda", "Π": r"\Pi", "Σ": r"\Sigma",
          "Φ": r"\Phi", "Ψ": r"\Psi", "Ω": r"\Omega"}
_SYMBOLS = {"≤": r"\le", "≥": r"\ge", "≠": r"\ne", "±": r"\pm", "×": r"\times", "·": r"\cdot", "√": r"\surd",
            "∞": r"\infty", "≈": r"\approx", "→": r"\to", "←": r"\leftarrow", "∈": r"\in", "∑": r"\sum",
            "∏": r"\prod", "−": "-", "∝": r"\propto", "≪": r"\ll", "≫": r"\gg", "∼": r"\sim", "′": r"'",
            **_GREEK}
_TEXT_SYMBOLS = {"§": r"\S{}", "–": "--", "—": "---", "‘": "`", "’": "'", "“": "``", "”": "''", "…": r"\dots{}",
                 "°": r"\textdegree{}", "µ": r"\textmu{}", "é": r"\'e", "ö": r"\"o", "ü": r"\"u"}
_ASCII_OPS = {"<=": r"\le", ">=": r"\ge", "!=": r"\ne", "->": r"\to", "+/-": r"\pm"}
_SUPER = dict(zip("⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺", "0123456789-+"))
_SUB = dict(zip("₀₁₂₃₄₅₆₇₈₉", "0123456789"))
_SUBSCRIPT_WORDS = {"inf": r"\infty", "chi": r"\chi", "fa": r"\mathrm{fa}", "max": r"\max", "min": r"\min"}

_GREEK_CHARS = "".join(_GREEK)
_TOKEN = re.compile(
    r"(?P<exp>(?<![\w\\])exp\((?P<expbody>[^()]{1,40})\))"
    r"|(?P<hat>(?<![\w\\])(?P<hatletter>[A-Za-z])-hat(?!\w))"
    r"|(?P<bar>(?<![\w\\])(?P<barletter>[A-Za-z])bar(?!\w))"
    r"|(?P<lambdav>(?<![\w\\])lambda(?P<lvletter>[A-Z])(?!\w))"
    r"|(?P<named>(?<![\w\\])(?:sqrt|oo)(?![\w]))"
    r"|(?P<range>(?<=\d)-(?=\d+(?:\.\d+)?e[+-]?\d))"
    r"|(?P<minus>(?:(?<=^)|(?<=[\s(\[=,;:/]))-(?=\d|\.\d|\[|\()|(?<=\s)-(?=\s))"
    r"|(?P<sci>(?<![\w.])[+-]?\d+(?:\.\d+)?e[+-]?\d{1,3}(?![\w.]))"
    r"|(?P<op>\+/-|<=|>=|!=|->)"
    r"|(?P<pow>\*\*(?P<powexp>-?\d+|[A-Za-z]))"
    r"|(?P<caret>\^(?:\((?P<cexp>[^()]{1,30})\)|(?P<cword>-?\w+)))"
    r"|(?P<greekword>(?<![\w\\])(?:alpha|beta|gamma|delta|lambda|sigma|chi|mu|pi|rho|tau|eta)(?![\w(]))"
    r"|(?P<sub>(?<![\w\\])(?P<base>[A-Za-z" + _GREEK_CHARS + r"])_(?P<index>[A-Za-z0-9" + _GREEK_CHARS
    + r"]{1,3})(?![\w]))"
    r"|(?P<accent>(?P<letter>[A-Za-z])(?P<mark>[\u0302\u0304]))"
    r"|(?P<super>[⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺]+)"
    r"|(?P<subs>[₀₁₂₃₄₅₆₇₈₉]+)"
    r"|(?P<symbol>[" + "".join(_SYMBOLS) + "])"
    r"|(?P<text>[" + "".join(_TEXT_SYMBOLS) + "])"
)

#: Plain-text mathematics that must not survive in generated LaTeX (a test reads every generated file).
ASCII_MATH = re.compile(r"<=|>=|!=|\*\*\w|(?<![\w.])\d+(?:\.\d+)?e[+-]?\d{1,3}(?![\w.])|(?<![\w\\])[A-Za-z]\\_[A-Za-z0-9]{1,3}(?![\w\\])"
                        r"|\+/-|(?<![\w\\])(?:[A-Za-z]-hat|[A-Za-z]bar|exp\(|sqrt|lambda[A-Z]|oo)(?!\w)")


_KINDS = ("range", "exp", "hat", "bar", "lambdav", "named", "minus", "sci", "op", "pow", "caret", "greekword", "sub", "accent", "super", "subs", "symbol", "text")


def _math(body: str) -> str:
    return rf"\ensuremath{{{body}}}"


def _sci(text: str) -> str:
    mant, exp = re.fullmatch(r"([+-]?\d+(?:\.\d+)?)e([+-]?\d+)", text).groups()
    exp = str(int(exp))
    power = f"10^{{{exp}}}"
    return _math(power if mant in ("1", "+1", "1.0") else rf"{mant}\times{power}")


def _convert(m: re.Match) -> str:
    kind = next(k for k in _KINDS if m.group(k) is not None)
    s = m.group(0)
    if kind == "range":  # 1e4-1e5: a range of powers of ten, an en dash
        return "--"
    if kind == "exp":  # exp(-lambdaV), exp(-V*lambda): the exponent as a power of e, itself converted
        body = latex_text(m.group("expbody").replace("*", " ")).replace(r"\ensuremath", "")
        return _math(f"e^{{{body}}}")
    if kind == "hat":
        return _math(rf"\hat{{{m.group('hatletter')}}}")
    if kind == "bar":
        return _math(rf"\bar{{{m.group('barletter')}}}")
    if kind == "lambdav":
        return _math(rf"\lambda {m.group('lvletter')}")
    if kind == "named":
        return _math({"sqrt": r"\surd", "oo": r"\infty"}[s])
    if kind == "minus":
        return _math("-")
    if kind == "sci":
        return _sci(s)
    if kind == "op":
        return _math(_ASCII_OPS[s])
    if kind == "pow":
        return _math(f"^{{{m.group('powexp')}}}")
    if kind == "caret":
        body = m.group("cexp") if m.group("cexp") is not None else m.group("cword")
        body = latex_text(body).replace(r"\ensuremath", "")  # the exponent's own notation, already in math
        return _math(f"^{{{body.strip()}}}")
    if kind == "greekword":
        return _math("\\" + s)
    if kind == "sub":
        base, index = m.group("base"), m.group("index")
        index = _SUBSCRIPT_WORDS.get(index) or "".join(_GREEK.get(c, c) + (" " if c in _GREEK else "") for c in index)
        return _math(f"{_GREEK.get(base, base)}_{{{index.strip()}}}")
    if kind == "accent":
        return _math((r"\hat" if m.group("mark") == "\u0302" else r"\bar") + f"{{{m.group('letter')}}}")
    if kind == "super":
        return _math("^{" + "".join(_SUPER[c] for c in s) + "}")
    if kind == "subs":
        return _math("_{" + "".join(_SUB[c] for c in s) + "}")
    if kind == "symbol":
        if s == "−":  # U+2212 is a minus sign, never a hyphen
            return _math("-")
        return _math(_SYMBOLS[s]) if _SYMBOLS[s].startswith("\\") else _SYMBOLS[s]
    return _TEXT_SYMBOLS[s]


def latex_text(text) -> str:
    r"""Plain text -> LaTeX: special characters escaped, plain-text mathematics in math mode (module docstring).

    >>> latex_text("P[Bin(M, p_D) <= m] = 1 - p_D**3, 1e+06 runs, ±3 %")
    'P[Bin(M, \\ensuremath{p_{D}}) \\ensuremath{\\le} m] = 1 \\ensuremath{-} \\ensuremath{p_{D}}\\ensuremath{^{3}}, \\ensuremath{10^{6}} runs, \\ensuremath{\\pm}3 \\%'
    """
    text = str(text)
    out, pos = [], 0
    for m in _TOKEN.finditer(text):
        out.append(latex_escape(text[pos:m.start()]))
        out.append(_convert(m))
        pos = m.end()
    out.append(latex_escape(text[pos:]))
    return "".join(out)
