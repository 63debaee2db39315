r"""Checks and build of the reproduction report (``paper/``): no typed result, no silent LaTeX failure.

Two rules keep the report honest:

* **No bare number.** Every digit in ``paper/sections/**/*.tex`` that describes a result comes from a
  generated macro (``\htval{...}``, see :mod:`hypotrack.reporting.macros`). :func:`bare_numbers` lists the
  digits that remain after removing what is allowed: macro arguments, references and citations
  (``\ref``, ``\label``, ``\cite*``, ``\input``, file names in ``\texttt``/``\htfigure``), the
  documents' own numbering (``Eq.~39``, ``Figs.~8--11``, ``Table~6.1``, ``Sec.~IV-A``, ``Prop.~1``,
  ``Algorithm~1``, the document ids ``000``--``004``), display equations (formulas, not results),
  single digits inside inline math (formula constants such as :math:`1-p_D`), and the text of
  ``\stated{...}`` (a value the documents state or the reader is told as a definition, never a
  measurement; use it sparingly).
* **The build fails loudly.** :func:`latex_log_problems` reads the LaTeX log and reports undefined
  control sequences (a missing generated macro, named), undefined references and citations, floats
  too large for their page, and missing generated values; :func:`layout_problems` adds every line
  overfull by more than :data:`OVERFULL_LIMIT_PT`, more than :data:`MAX_PAGES_BEFORE_APPENDIX` pages
  before the appendix (:func:`pages_before_appendix`, from the ``.aux``) and every garbled phrase of the
  PDF's text (:func:`text_problems`: ASCII mathematics, a hyphen for a minus sign, an undated reference,
  "1 runs", an empty template value). :func:`bare_document_figures` keeps every figure of a document
  named with its document ("document 000's Fig.~15"; a test checks the sections).
"""

from __future__ import annotations

import re
from pathlib import Path

__all__ = ["MAX_PAGES_BEFORE_APPENDIX", "OVERFULL_LIMIT_PT", "bare_document_figures", "bare_numbers", "build_pdf",
           "latex_log_problems", "layout_problems", "overfull_boxes", "overfull_hboxes", "pages_before_appendix", "pdf_text_problems",
           "scan_sections", "text_problems"]

_DOC_REF = re.compile(
    r"(?:Eqs?\.|Figs?\.|Tables?|Secs?\.|Sections?|Prop\.|Propositions?|Algorithms?|Appendix|Lemma|Theorem|"
    r"Chapter|\\S|§)(?:~|\s)*"
    r"(?:[0-9IVX]+(?:[.\-][0-9A-Z]+)*(?:\s*(?:--|–|,|and|or|~)\s*)?)+")
_DOC_ID = re.compile(r"(?<![\d.])00[0-4](?![\d.])")
_ARG_COMMANDS = ("htval", "htn", "htifvalue", "ref", "eqref", "label", "cite", "citep", "citet", "citealp", "input", "include",
                 "texttt", "url", "includegraphics", "stated", "begin", "end", "hspace", "vspace")
_DISPLAY = re.compile(r"\\begin\{(equation|align|gather|multline|eqnarray)\*?\}.*?\\end\{\1\*?\}", re.S)
_INLINE_MATH = re.compile(r"\$[^$]*\$")
_NUMBER = re.compile(r"\d+(?:[.,{}]*\d+)*")


def _strip_command_args(text: str, name: str) -> str:
    r"""Remove ``\name[opt]{arg}`` (balanced braces) from ``text``."""
    out, i = [], 0
    pat = re.compile(r"\\" + name + r"\*?(?![A-Za-z])")
    while True:
        m = pat.search(text, i)
        if not m:
            out.append(text[i:])
            return "".join(out)
        out.append(text[i:m.start()])
        j = m.end()
        while j < len(text) and text[j] in " \t":
            j += 1
        if j < len(text) and text[j] == "[":
            j = text.index("]", j) + 1
        if j < len(text) and text[j] == "{":
            depth = 0
            for k in range(j, len(text)):
                depth += {"{": 1, "}": -1}.get(text[k], 0)
                if depth == 0:
                    j = k + 1
                    break
        out.append(" " + "\n" * text.count("\n", m.start(), j))  # keep line numbers
        i = j


def _strip_htfigure(text: str) -> str:
    r"""``\htfigure{path}{width}{caption}``: the path and width are not results; keep the caption."""
    return re.sub(r"\\htfigure\{[^}]*\}\{[^}]*\}", r"\\htfigure", text)


def bare_numbers(tex: str) -> list[tuple[int, str]]:
    """``(line, context)`` for every digit run in ``tex`` outside the allowed contexts (module docstring)."""
    lines = tex.split("\n")
    text = "\n".join(re.sub(r"(?<!\\)%.*", "", ln) for ln in lines)  # comments
    text = _DISPLAY.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    text = _strip_htfigure(text)
    for name in _ARG_COMMANDS:
        text = _strip_command_args(text, name)
    text = re.sub(r"\\S~?\s*\d+(?:\.\d+)*", " ", text)  # \S5: a section sign with its number
    text = re.sub(r"\\[A-Za-z]+", " ", text)  # remaining command names (\textbf, \linewidth, ...)

    def math(m):
        # digits in inline math: single-digit formula constants (1-p_D, 6/\pi) and ^/_ indices are allowed
        body = re.sub(r"[\^_]\{?\d+\}?", " ", m.group(0))
        return re.sub(r"(?<![\d.])\d(?!\.?\d|\{,\}\d)", " ", body)

    text = _INLINE_MATH.sub(math, text)
    text = _DOC_REF.sub(" ", text)
    text = _DOC_ID.sub(" ", text)
    hits = []
    for no, line in enumerate(text.split("\n"), 1):
        for m in _NUMBER.finditer(line):
            hits.append((no, lines[no - 1].strip()[:160] if no <= len(lines) else m.group(0)))
    return hits


_DOC_FIGURE = re.compile(r"Figs?\.(?:~|\s)*\d")
_NAMED_BEFORE = re.compile(r"00[0-4](?:'s|,)?(?:~|\s)+(?:\\emph\{)?$")


def bare_document_figures(tex: str) -> list[tuple[int, str]]:
    """``(line, context)`` of every figure of a document cited without its document: "Fig.~15" must read
    "document 000's Fig.~15" (or "000, Fig.~15"), because a bare figure number names the report's own
    figures (which the report cites by ``\\ref``, never by a typed number)."""
    found = []
    for m in _DOC_FIGURE.finditer(tex):
        if not _NAMED_BEFORE.search(tex[max(0, m.start() - 30):m.start()]):
            found.append((tex.count("\n", 0, m.start()) + 1, tex[max(0, m.start() - 40):m.end() + 10].replace("\n", " ")))
    return found


def scan_sections(sections_dir) -> dict[str, list[tuple[int, str]]]:
    """:func:`bare_numbers` of every ``.tex`` file under ``sections_dir`` (relative path -> hits)."""
    root = Path(sections_dir)
    found = {}
    for path in sorted(root.rglob("*.tex")):
        hits = bare_numbers(path.read_text())
        if hits:
            found[str(path.relative_to(root))] = hits
    return found


def overfull_boxes(log: str) -> list[str]:
    """The ``Overfull \\hbox``/``\\vbox`` lines of a LaTeX log."""
    return re.findall(r"^Overfull \\[hv]box .*$", log, re.M)


def latex_log_problems(log: str) -> list[str]:
    """Problems that must fail the paper build, each a sentence naming its cause.

    LaTeX errors (a missing generated macro by name, an undefined control sequence, any other ``!``
    error) come first; when there are none, undefined references and citations and floats too large
    for their page (which are only meaningful after a complete run).
    """
    problems = []
    for m in re.finditer(r"^! (.*)$", log, re.M):
        msg = m.group(1)
        missing = re.match(r"Package hypotrack Error: generated value (\w+) is missing", msg)
        figure = re.match(r"Package hypotrack Error: figure (\S+) was not generated", msg)
        if missing:
            problems.append(f"generated macro \\{missing.group(1)} is missing (no claim or macros.csv row defines it)")
        elif figure:
            problems.append(f"figure {figure.group(1)} was not generated (no rule wrote it)")
        elif msg.startswith("Undefined control sequence"):
            cs = re.match(r"l\.\d+ .*?(\\[A-Za-z@]+)\s*$", log[m.end():].lstrip("\n").split("\n", 1)[0])
            problems.append(f"undefined control sequence {cs.group(1) if cs else '(see the log)'}")
        else:
            problems.append(f"LaTeX error: {msg}")
    if not problems:
        for m in re.finditer(r"LaTeX Warning: Reference `([^']+)' on page \d+ undefined", log):
            problems.append(f"undefined reference {m.group(1)}")
        for m in re.finditer(r"(?:LaTeX|Package natbib) Warning: Citation `([^']+)' on page \d+ undefined", log):
            problems.append(f"undefined citation {m.group(1)}")
    for m in re.finditer(r"LaTeX Warning: Float too large for page by ([\d.]+pt) on input line (\d+)", log):
        problems.append(f"float too large for its page by {m.group(1)} (input line {m.group(2)})")
    return list(dict.fromkeys(problems))


def build_pdf(source_dir, inputs_dir, build_dir, pdf, log) -> list[str]:
    """Compile ``<source_dir>/ms.tex`` into ``pdf``; return the overfull-box lines, raise on a problem.

    The sources stay where they are: latexmk runs in ``source_dir`` with ``-outdir=build_dir``, and
    ``generated/...`` (macros, ledger table, figures) is found under ``inputs_dir`` through
    ``TEXINPUTS``; nothing is written into the source tree. Any path may be relative or absolute.
    Raises ``RuntimeError`` listing :func:`latex_log_problems` (a missing macro by name, an undefined
    reference or citation, a float too large for its page) or LaTeX's own failure.
    """
    import os
    import shutil
    import subprocess

    source_dir, inputs_dir, build_dir = (Path(p).resolve() for p in (source_dir, inputs_dir, build_dir))
    build_dir.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ, TEXINPUTS=f".{os.pathsep}{inputs_dir}{os.pathsep}",
               BIBINPUTS=f"{source_dir}{os.pathsep}", max_print_line="100000")  # unwrapped log lines
    cmd = ["latexmk", "-pdf", "-interaction=nonstopmode", f"-outdir={build_dir}", "ms.tex"]
    with open(log, "w") as out:
        run = subprocess.run(cmd, cwd=source_dir, env=env, stdout=out, stderr=subprocess.STDOUT, check=False)
    tex_log = (build_dir / "ms.log").read_text(errors="replace") if (build_dir / "ms.log").exists() else ""
    problems = latex_log_problems(tex_log)
    overfull = overfull_boxes(tex_log)
    with open(log, "a") as out:
        out.write(f"\nhypotrack: {len(overfull)} overfull boxes; problems: {problems or 'none'}\n")
    if problems or run.returncode != 0:
        raise RuntimeError(f"paper build failed ({build_dir / 'ms.log'}): "
                           + ("; ".join(problems) if problems else f"latexmk exited with {run.returncode}"))
    # Layout and text rules, each failing the build with its list: no line overfull by more than
    # OVERFULL_LIMIT_PT, the paper before its appendix at most MAX_PAGES_BEFORE_APPENDIX pages, and no
    # garbled phrase, ASCII mathematics or unresolved value in the PDF's text (text_problems).
    wide = overfull_hboxes(tex_log)
    aux = build_dir / "ms.aux"
    pages = pages_before_appendix(aux.read_text(errors="replace")) if aux.exists() else None
    garbled = pdf_text_problems(build_dir / "ms.pdf", inputs_dir / "generated" / "figures")
    with open(log, "a") as out:
        out.write(f"hypotrack: {len(wide)} lines overfull by more than {OVERFULL_LIMIT_PT:g} pt; {pages} pages before "
                  f"the appendix; {len(garbled)} garbled phrases in the PDF's text\n"
                  + "".join(f"  {g}\n" for g in [*wide, *garbled]))
    layout = layout_problems(wide, pages, garbled)
    if layout:
        raise RuntimeError(f"paper build failed ({build_dir / 'ms.log'}): " + "; ".join(layout))
    Path(pdf).parent.mkdir(parents=True, exist_ok=True)
    shutil.copyfile(build_dir / "ms.pdf", pdf)
    return overfull


#: A line may stick out of its box by at most this much (TeX's own \hfuzz is 0.1 pt; 1 pt is invisible in print).
OVERFULL_LIMIT_PT = 1.0
#: The paper, abstract to references, may take at most this many pages before its appendix.
MAX_PAGES_BEFORE_APPENDIX = 30
#: The label ms.tex sets just after \appendix (on a new page).
APPENDIX_LABEL = "ht:appendix-start"


def overfull_hboxes(log: str, limit_pt: float = OVERFULL_LIMIT_PT) -> list[str]:
    """The ``Overfull \\hbox`` lines of a LaTeX log wider than ``limit_pt``, each with its source lines."""
    found = []
    for m in re.finditer(r"^Overfull \\hbox \(([\d.]+)pt too wide\) (.*)$", log, re.M):
        if float(m.group(1)) > limit_pt:
            found.append(f"overfull line by {m.group(1)} pt {m.group(2)}")
    return found


def pages_before_appendix(aux: str, label: str = APPENDIX_LABEL) -> int:
    """Pages before the appendix: one less than the page of ``label`` in the ``.aux`` (the appendix starts
    on a new page). A missing label is an error naming it (ms.tex must set it after ``\\appendix``)."""
    m = re.search(r"\\newlabel\{" + re.escape(label) + r"\}\{\{[^}]*\}\{(\d+)\}", aux)
    if not m:
        raise ValueError(f"label {label!r} not in the .aux: set \\label{{{label}}} right after \\appendix in ms.tex")
    return int(m.group(1)) - 1


def layout_problems(wide, pages, garbled, max_pages: int = MAX_PAGES_BEFORE_APPENDIX) -> list[str]:
    """The build's layout and text failures as sentences (empty when the paper passes)."""
    problems = []
    if wide:
        problems.append(f"{len(wide)} lines overfull by more than {OVERFULL_LIMIT_PT:g} pt: " + "; ".join(wide))
    if pages is None:
        problems.append(f"no .aux to measure the pages before the appendix (label {APPENDIX_LABEL})")
    elif pages > max_pages:
        problems.append(f"{pages} pages before the appendix, more than {max_pages}")
    if garbled:
        problems.append(f"{len(garbled)} garbled phrases in the PDF's text: " + "; ".join(garbled))
    return problems


# Function words only: a table's cells and a figure's tick labels sit side by side in the PDF's text, so
# "scans scans" or "km km" there is layout, not prose; "the the" and "at at" never are.
_REPEATED_WORD = re.compile(r"\b(the|a|an|at|of|in|is|to|and|or|for|on|with|from|by)\s+\1\b", re.I)
# "peaks at peak 8.3 MiB": a generated value repeating the word before it ("X by X" is an idiom: left out)
_STEM_ECHO = re.compile(r"\b(?P<w>[A-Za-z]{4})[a-z]*\s+(?:at|of|in|is|to|a|the)\s+(?P=w)[a-z]*\b", re.I)
_AT_X_AT = re.compile(r"\bat\s+[A-Za-z]+\s+at\b")
_TEXT_RULES = (
    ("a repeated word", _REPEATED_WORD),
    ("a word echoed across a generated value", _STEM_ECHO),
    ("'at ... at'", _AT_X_AT),
    ("ASCII mathematics", re.compile(r"<=|>=|!=|\*\*\w|\+/-|(?<![\w.])\d+(?:\.\d+)?e[+-]\d{1,3}(?![\w.])"
                                     r"|(?<![\w])[A-Za-z]_[A-Za-z]{1,3}\b")),
    ("ASCII mathematics from a note", re.compile(r"(?<![\w\\])(?:[A-Za-z]-hat|[A-Za-z]bar|exp\(|sqrt|lambda\w*|oo)(?!\w)"
                                               r"|->|(?<![\w.])p\\_[A-Za-z]")),
    ("a hyphen used as a minus sign", re.compile(r"(?:^|(?<=[\s(\[=,;:]))-(?=\d|\.\d)|(?<=\s)-(?=\s)")),
    ("an unresolved template or value", re.compile(r"\{[a-z_]+\}|\bnan\b|\bNone\b|\?\?")),
    ("a citation shown by its key", re.compile(r"\[[a-z]{2,4}, n\.d\.\]")),
    ("a reference without a date or title", re.compile(r"\bn\.d\.|\[untitled", re.I)),
    ("a count with the wrong number", re.compile(r"(?<![\d.,])1 (?:[a-z]+ )?(?:runs|rows|objects|scans|seeds|claims|problems|births|"
                                                   r"cells|settings|steps|hypotheses|tracks|sizes|times)\b"
                                                   r"|\babout 1 \w+s\b")),
    ("a value missing from a template", re.compile(r"\b(?:at|scan|of|by|to)\s+[–-]\s+(?:moving|m/s|at|of|and)\b")),
    ("'seed 000' where a document is meant", re.compile(r"\bseeds? 00[0-4]\b")),
)


def _pdftotext(pdf) -> str:
    import subprocess

    # -layout keeps a table's cells on their row, apart: cells side by side are then cut at the wide gaps
    # between them (text_problems), so two cells never read as one phrase ("away from | from the").
    out = subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True, text=True, check=True).stdout
    return "\n".join(" ".join(ln.split()) if not re.search(r"\S {3,}\S", ln)
                     else "¦ " + " ¦ ".join(" ".join(c.split()) for c in re.split(r" {3,}", ln.strip())) + " ¦"
                     for ln in out.splitlines())


def pdf_text_problems(pdf, figures_dir=None) -> list[str]:
    """:func:`text_problems` of a PDF's text (``pdftotext``, poppler); [] when pdftotext is absent.

    The figures' own text (tick labels, legends: every line ``pdftotext`` finds in a PDF under
    ``figures_dir``) is removed first: the figures are checked where they are drawn, and their labels set
    side by side would read as garbled prose."""
    import shutil

    if shutil.which("pdftotext") is None:
        return []
    text = _pdftotext(pdf)
    if figures_dir is not None and Path(figures_dir).is_dir():
        drawn = {ln.strip() for fig in sorted(Path(figures_dir).rglob("*.pdf")) for ln in _pdftotext(fig).splitlines()}
        drawn.discard("")
        text = "\n".join(ln for ln in text.splitlines() if ln.strip() not in drawn)
    return text_problems(text)


def text_problems(text: str) -> list[str]:
    """Garbled phrases in the report's text as a reader sees it (``pdftotext`` of the PDF), each
    naming the rule and quoting the context: a repeated word ("at at"), a word echoed across a
    generated value ("peaks at peak"), "at crossover at", ASCII mathematics (``<=``, ``p_D``,
    ``1e+06``, ``n-hat``, ``exp(-lambdaV)``, ``M -> oo``, ``Vbar``, ``sqrt``), a hyphen used as a minus sign,
    an unresolved template (``{name}``, ``nan``, ``??``), a citation shown by its key or without a date or
    title, a count of one with a plural noun ("1 runs", "about 1 runs"), a template whose value is missing
    ("born at scan – moving at"), and "document 000" where the document is meant."""
    flat = re.sub(r"-\n(?=[a-z])", "", text)  # undo end-of-line hyphenation
    flat = re.sub(r"\s+", " ", flat)
    found = []
    for name, rule in _TEXT_RULES:
        for m in rule.finditer(flat):
            found.append(f"{name}: ...{flat[max(0, m.start() - 40):m.end() + 40]}...")
    return found
