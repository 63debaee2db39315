"""The report quotes no typed result: every number in paper/sections comes from a generated macro,
and the build fails loudly (missing macro by name, undefined reference, oversized float)."""

import shutil
from pathlib import Path

from hypotrack.reporting.paper import bare_numbers, latex_log_problems, overfull_boxes, scan_sections

PAPER = Path(__file__).resolve().parents[3] / "paper"


def test_paper_sections_have_no_bare_numbers():
    found = scan_sections(PAPER / "sections")
    assert found == {}, "numbers typed in the paper (use a generated macro): " + "; ".join(
        f"{f}:{line}: {text}" for f, hits in found.items() for line, text in hits)


def test_a_bare_number_added_to_a_copy_of_a_section_fails_the_scan(tmp_path):
    copy = tmp_path / "sections"
    shutil.copytree(PAPER / "sections", copy)
    target = copy / "discussion.tex"
    target.write_text(target.read_text() + "\nThe MHT's MOSPA is 6.7~\\% above the published value.\n")
    found = scan_sections(copy)
    assert list(found) == ["discussion.tex"] and any("6.7" in text for _, text in found["discussion.tex"])


def test_allowed_contexts_and_caught_numbers():
    allowed = (r"Eq.~39 and Eqs.~32--33, Figs.~8--11, Table~6.1, Sec.~IV-A, Prop.~1, (000, Algorithm~1) of 004; "
               r"\htval{htSwapsRmsMinimumRep} swaps \citep{faber2019} Section~\ref{sec:gaps}, \texttt{fig_4_2.py}, "
               r"$1-p_D$, $A(M+1,m)$, $x^{2}$, $\sigma_q^2$, \stated{0.8518} % a comment with 42"
               "\n\\begin{equation}A(10,5)=63{,}591\\end{equation}\n"
               r"\htfigure{generated/figures/ssa50/fig_6}{0.85}{Weights (cf. 000, Fig.~6).}")
    assert bare_numbers(allowed) == []
    for typed in ("at a nearly constant 0.02~s per parent", r"equal to $3\times10^{-14}$", r"$1.8\times10^7$ children",
                  "88~\\% of runs", "between 0.15 and 0.46", r"100{,}000 steps", r"$T=20$", "45 objects",
                  r"\htfigure{a}{0.5}{after 5 births}"):
        hits = bare_numbers("text\n" + typed)
        assert hits and hits[0][0] == 2, typed


def test_latex_log_problems_name_their_cause():
    errors = "\n".join([
        "! Package hypotrack Error: generated value htSwapsRmsMinimumRep is missing.",
        "! Undefined control sequence.",
        r"l.12 ... \htSwapsRateFar",
        "LaTeX Warning: Reference `sec:gapz' on page 3 undefined on input line 40.",
    ])
    # errors come first; the undefined references of an incomplete run are not reported with them
    assert latex_log_problems(errors) == [
        r"generated macro \htSwapsRmsMinimumRep is missing (no claim or macros.csv row defines it)",
        r"undefined control sequence \htSwapsRateFar"]
    complete = "\n".join([
        "LaTeX Warning: Reference `sec:gapz' on page 3 undefined on input line 40.",
        "Package natbib Warning: Citation `nobody2020' on page 2 undefined on input line 7.",
        "LaTeX Warning: Float too large for page by 97.3pt on input line 88.",
        r"Overfull \hbox (12.3pt too wide) in paragraph at lines 4--9",
    ])
    assert latex_log_problems(complete) == [
        "undefined reference sec:gapz", "undefined citation nobody2020",
        "float too large for its page by 97.3pt (input line 88)"]
    assert overfull_boxes(complete) == [r"Overfull \hbox (12.3pt too wide) in paragraph at lines 4--9"]
    assert latex_log_problems("Output written on ms.pdf (12 pages).") == []


def _mini_paper(tmp_path, body, appendix="\n\\clearpage\\appendix\\label{ht:appendix-start}An appendix."):
    """A source tree with the report's own \\htval definition, and generated inputs elsewhere; ``appendix``
    ends the body (the build measures the pages before the appendix from its label)."""
    src, gen = tmp_path / "src", tmp_path / "results" / "paper"
    src.mkdir(parents=True)
    (gen / "generated").mkdir(parents=True)
    (gen / "generated" / "macros.tex").write_text("\\newcommand{\\htSwapsRmsMinimumRep}{4}\n")
    preamble = (PAPER / "ms.tex").read_text().split("\\title{")[0]  # the report's preamble, macros included
    (src / "ms.tex").write_text(preamble.replace("\\usepackage{natbib}", "") + "\\begin{document}\n" + body
                                + appendix + "\n\\end{document}\n")
    return src, gen


def test_paper_build_fails_naming_a_missing_macro_and_writes_nothing_in_the_sources(tmp_path):
    import pytest

    from hypotrack.reporting.paper import build_pdf

    if shutil.which("latexmk") is None:
        pytest.skip("latexmk not installed")
    src, gen = _mini_paper(tmp_path, "Minimum at \\htval{htSwapsRmsMinimumRep} swaps.")
    build_pdf(src, gen, gen / "build", gen / "out.pdf", tmp_path / "ok.log")
    assert (gen / "out.pdf").stat().st_size > 0 and sorted(p.name for p in src.iterdir()) == ["ms.tex"]
    src, gen = _mini_paper(tmp_path / "missing", "Minimum at \\htval{htSwapsRmsMinimumRep} swaps, rate "
                           "\\htval{htSwapsRateFarRep}; see Section~\\ref{sec:nowhere}.")
    with pytest.raises(RuntimeError, match=r"generated macro \\htSwapsRateFarRep is missing"):
        build_pdf(src, gen, gen / "build", gen / "out.pdf", tmp_path / "missing.log")
    src, gen = _mini_paper(tmp_path / "fig", "\\htfigure{generated/figures/swaps/fig_9_9}{0.5}{A renamed figure.}")
    with pytest.raises(RuntimeError, match="figure generated/figures/swaps/fig_9_9 was not generated"):
        build_pdf(src, gen, gen / "build", gen / "out.pdf", tmp_path / "fig.log")
    src, gen = _mini_paper(tmp_path / "ref", "See Section~\\ref{sec:nowhere}.")
    with pytest.raises(RuntimeError, match="undefined reference sec:nowhere"):
        build_pdf(src, gen, gen / "build", gen / "out.pdf", tmp_path / "ref.log")


def test_paper_layout_rules_fail_the_build_naming_the_cause(tmp_path):
    """An overfull line over 1 pt, more than 30 pages before the appendix, a missing appendix label and ASCII
    mathematics in the text each fail the build; a paper within the rules builds."""
    import pytest

    from hypotrack.reporting.paper import MAX_PAGES_BEFORE_APPENDIX, build_pdf

    if shutil.which("latexmk") is None:
        pytest.skip("latexmk not installed")
    ok = "Minimum at \\htval{htSwapsRmsMinimumRep} swaps." + "\\newpage x" * (MAX_PAGES_BEFORE_APPENDIX - 1)
    src, gen = _mini_paper(tmp_path / "ok", ok)
    build_pdf(src, gen, gen / "build", gen / "out.pdf", tmp_path / "ok.log")
    assert (gen / "out.pdf").exists()
    src, gen = _mini_paper(tmp_path / "long", ok + "\\newpage x")
    with pytest.raises(RuntimeError, match=f"{MAX_PAGES_BEFORE_APPENDIX + 1} pages before the appendix"):
        build_pdf(src, gen, gen / "build", gen / "out.pdf", tmp_path / "long.log")
    assert not (gen / "out.pdf").exists()
    src, gen = _mini_paper(tmp_path / "wide", "\\noindent\\hbox to \\linewidth{\\hskip 1.2\\linewidth}")
    with pytest.raises(RuntimeError, match=r"1 lines overfull by more than 1 pt: overfull line by \d"):
        build_pdf(src, gen, gen / "build", gen / "out.pdf", tmp_path / "wide.log")
    src, gen = _mini_paper(tmp_path / "nolabel", "Text.", appendix="")
    with pytest.raises(ValueError, match="ht:appendix-start"):
        build_pdf(src, gen, gen / "build", gen / "out.pdf", tmp_path / "nolabel.log")
    src, gen = _mini_paper(tmp_path / "ascii", "The mean error is n-hat minus n, and z = -1.37.")
    with pytest.raises(RuntimeError, match="garbled phrases"):
        build_pdf(src, gen, gen / "build", gen / "out.pdf", tmp_path / "ascii.log")


def test_pages_before_appendix_reads_the_label_page():
    from hypotrack.reporting.paper import layout_problems, overfull_hboxes, pages_before_appendix

    aux = "\\newlabel{sec:x}{{1}{3}}\n\\newlabel{ht:appendix-start}{{7}{20}{Conclusions}{section*.57}{}}\n"
    assert pages_before_appendix(aux) == 19
    log = ("Overfull \\hbox (0.99303pt too wide) in paragraph at lines 1--2\n"
           "Overfull \\hbox (1.1731pt too wide) in paragraph at lines 8--8\n"
           "Overfull \\vbox (30.0pt too high) has occurred while \\output is active\n")
    assert overfull_hboxes(log) == ["overfull line by 1.1731 pt in paragraph at lines 8--8"]
    assert layout_problems([], 30, []) == [] and "31 pages" in layout_problems([], 31, [])[0]


def test_the_documents_figures_are_named_with_their_document():
    """A typed figure number is a document's figure, so it carries its document ("document 000's Fig.~15");
    the report's own figures are cited by \\ref. Checked on every section and on a case that must fail."""
    from hypotrack.reporting.paper import bare_document_figures

    for path in sorted((PAPER / "sections").rglob("*.tex")):
        assert bare_document_figures(path.read_text()) == [], path.name
    assert bare_document_figures("as document 000's Fig.~15 and (cf. 000, Figs.~8--11) show, Fig.~\\ref{fig:a}") == []
    hits = bare_document_figures("line one\n\\paragraph{Swaps (Figs.~5.1--5.3).} and its Fig. 4.2 claim")
    assert [line for line, _ in hits] == [2, 2]


def test_counts_pluralise_and_a_missing_value_drops_its_sentence(tmp_path):
    """\\htn prints "1 run" / "3 runs" / "1 child" / "2 children"; \\htifvalue drops text around a "--" value."""
    import subprocess

    import pytest

    from hypotrack.reporting.paper import build_pdf

    if shutil.which("latexmk") is None or shutil.which("pdftotext") is None:
        pytest.skip("latexmk or pdftotext not installed")
    src, gen = _mini_paper(tmp_path, "A \\htn{htOne}{run}, B \\htn{htThree}{run}, C \\htn[children]{htOne}{child}, "
                                     "D \\htn[children]{htThree}{child}. \\htifvalue{htNone}{Born at scan \\htval{htNone}.}"
                                     "\\htifvalue{htThree}{Seen in \\htval{htThree} scans.}")
    (gen / "generated" / "macros.tex").write_text("\\newcommand{\\htOne}{1}\n\\newcommand{\\htThree}{3}\n"
                                                  "\\newcommand{\\htNone}{--}\n")
    build_pdf(src, gen, gen / "build", gen / "out.pdf", tmp_path / "ok.log")
    text = " ".join(subprocess.run(["pdftotext", str(gen / "out.pdf"), "-"], capture_output=True, text=True,
                                   check=True).stdout.split())
    assert "A 1 run, B 3 runs, C 1 child, D 3 children." in text
    assert "Born at" not in text and "Seen in 3 scans." in text
