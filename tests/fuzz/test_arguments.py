"""Every subcommand, driven with generated command lines.

The command lines are built from the parser itself (every subcommand and
option ``adapt --help`` lists, so a subcommand added later is fuzzed too):
positional arguments and paths come from the pool of good and bad inputs
(missing files, folders, garbage, the wrong kind of file), option values from
lists of awkward numbers and text (NaN, infinities, 1e308, negative, empty,
non-ASCII digits, undecodable file-name bytes), and outputs from fresh
folders, missing folders, wrong extensions, special files and the inputs
themselves.  Values that would only make valid work long (a ``--max-iter`` of
500) are left out so that the test stays fast; the limits themselves are
fuzzed with values far beyond them.
"""

from __future__ import annotations

import argparse

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from adapt.cli import build_parser

from .harness import Pool, examples, run_checked


def _leaves(parser: argparse.ArgumentParser, prefix: tuple[str, ...] = ()) -> dict[tuple[str, ...], argparse.ArgumentParser]:
    found: dict[tuple[str, ...], argparse.ArgumentParser] = {}
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                found.update(_leaves(sub, prefix + (name,)) or {prefix + (name,): sub})
    return found


COMMANDS = _leaves(build_parser())

NUMBERS = ["0", "1", "2", "-1", "-0", "0.5", "3", "nan", "inf", "-inf", "1e9", "1e308", "-1e308",
           "100000000",
           "1e-9", "1e-300", "abc", "", " 3", "0x10", "1_0", "٣", "99999999999999999999999"]
TEXT = st.lists(st.characters(blacklist_categories=("Cc", "Cs"))
                | st.sampled_from(["\udcff", "\udc80", "^", "(", ")", "+", "*", "|", "<", ">", "..",
                                   " "]), max_size=8).map("".join)

#: Which pool files fit which positional argument (the others are tried too, less often).
FITS = {
    "files": ["count.soar", "wj.soar", "broken.soar", "empty.txt"],
    "scenario": ["scene.yaml", "plain.yaml", "textured.yaml"],
    "real": ["real.png", "grey16.png", "tiny.png", "other-size.png"],
    "synthetic": ["synth.png", "real.png", "grey16.png"],
    "trace": ["wj5.jsonl", "wj3.jsonl", "wj1.jsonl"],
    "a": ["wj5.jsonl", "wj1.jsonl"],
    "b": ["wj5.jsonl", "wj3.jsonl"],
    "rules": ["wj.soar", "count.soar", "broken.soar"],
}
BAD_INPUTS = ["missing.yaml", "folder", "empty.txt", "garbage.bin", "truncated.png", "/dev/null", "/dev/zero", "-",
              "x" * 300, "\udcff.yaml", "inputs/count.soar/x"]
OUTPUT_NAMES = ["a.png", "a.jpg", "a.tif", "a.txt", "a.html", "a.jsonl", "a.mp4", "a.avi", "noext",
                "new/deeper/a.png", "new/deeper/t.jsonl", "new/page.html", "out-dir", ""]
OUTPUT_OPTIONS = {"out", "labels", "video", "trace"}
WORK_OPTIONS = {"max_decisions", "max_frames", "max_iter", "samples", "horizon", "t", "fps"}
WME_TEXT = ["57", "0", "(S1 ^count 3)", "(S1 ^steps 2)", "S1 ^io", "(S1 ^operator O3 +)", "", "+",
            "(", "^", "(S1 ^)", "S1 ^a b c d", "²"]


#: Files a pool input reads in turn (a scenario's rule file).
INDIRECT = {"scene.yaml": ["perception.soar"],
            "textured.yaml": ["sources.soar", "perception.soar", "figures/floor.png"]}
INPUT_OPTIONS = {"real", "rules"}


@st.composite
def command_lines(draw: st.DrawFn, pool: Pool, words: tuple[str, ...]) -> list[str]:
    parser = COMMANDS[words]
    out_dir = pool.outputs()
    inputs: list[str] = []  # the pool files this command line reads: an output may name them

    def a_path(dest: str) -> str:
        choice = draw(st.integers(0, 9))
        if dest in FITS and choice < 6:
            name = draw(st.sampled_from(FITS[dest]))
        elif choice < 8:
            return draw(st.sampled_from(BAD_INPUTS))
        else:
            name = draw(st.sampled_from(sorted(pool.files)))
        inputs.append(pool.path(name))
        inputs.extend(pool.path(n) for n in INDIRECT.get(name, ()))
        return pool.path(name)

    def an_output() -> str:
        choice = draw(st.integers(0, 9))
        if choice < 6 or (choice < 8 and not inputs):
            return str(out_dir / draw(st.sampled_from(OUTPUT_NAMES)))
        if choice < 8:  # one of its inputs: must be refused
            return draw(st.sampled_from(inputs))
        return draw(st.sampled_from(["/proc/x.png", "/dev/null", str(out_dir), "/", "inputs"]))

    argv = list(words)
    options: list[str] = []
    outputs: list[str] = []
    for action in parser._actions:
        if action.dest == "help":
            continue
        if not action.option_strings:  # positional
            count = draw(st.integers(1, 3)) if action.nargs == "+" else 1
            argv += [a_path(action.dest) for _ in range(count)]
            continue
        if not action.required and not draw(st.booleans()):
            continue
        flag = action.option_strings[0]
        if action.nargs == 0:
            options.append(flag)
            continue
        if action.dest in OUTPUT_OPTIONS:
            outputs.append(flag)
            continue
        if action.dest in INPUT_OPTIONS:
            value = a_path(action.dest)
        elif action.dest == "wme":
            value = draw(st.sampled_from(WME_TEXT) | TEXT)
        elif action.choices is not None:
            value = draw(st.sampled_from([str(c) for c in action.choices] + ["0", "9", "x"]))
        elif action.type in (int, float) or action.dest in WORK_OPTIONS or action.dest in ("depth", "level"):
            value = draw(st.sampled_from(NUMBERS))
        elif action.dest == "decisions":
            value = draw(st.sampled_from(["1..3", "2", "..4", "5..", "9..3", "0..0", "100..200", "a..b",
                                          "-3..-1", ""]))
        else:
            value = draw(st.sampled_from(["S1", "O3", "Z99", "water-jug*apply*fill", "nosuch", "ball"])
                         | TEXT)
        options += [flag, value]
    for flag in outputs:  # after the inputs are known
        options += [flag, an_output()]
    if draw(st.integers(0, 19)) == 0:
        options.append(draw(st.sampled_from(["--nosuch", "extra", "--json=1", "-"])))
    return argv + options


@pytest.mark.parametrize("words", sorted(COMMANDS), ids=" ".join)
def test_generated_command_lines_keep_the_contract(pool: Pool, words: tuple[str, ...]) -> None:
    @settings(max_examples=examples(12), deadline=None, derandomize=True,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
    @given(st.data())
    def check(data: st.DataObject) -> None:
        run_checked(pool, data.draw(command_lines(pool, words)))

    check()


def test_every_subcommand_is_fuzzed() -> None:
    assert {" ".join(w) for w in COMMANDS} >= {
        "run", "check", "schemas list", "rules run", "rules check", "render", "imagine", "mmd",
        "sync", "trace show", "trace wm", "trace why", "trace stats", "trace diff", "trace html"}


@pytest.mark.parametrize("argv", [
    [], ["--nosuch"], ["nosuch"], ["rules"], ["trace"], ["trace", "show"], ["--version"], ["--help"],
    ["trace", "why", "{wj5.jsonl}", "--depth", "-5", "--wme", "57"],
    ["trace", "why", "{wj5.jsonl}", "--wme", ""],
    ["rules", "run", "{wj.soar}", "--trace", "{wj.soar}"],
    ["trace", "html", "{wj5.jsonl}", "--out", "{wj5.jsonl}"],
    ["trace", "show", "{wj5.jsonl}", "--rule", "nosuch"],
    ["trace", "show", "{wj5.jsonl}", "--id", "Z99"],
    ["imagine", "{scene.yaml}", "--horizon", "1e9"],
    ["imagine", "{scene.yaml}", "--horizon", "1", "--samples", "100000000"],
    ["render", "{scene.yaml}", "--out", "x.png", "--t", "1e9"],
    ["render", "{scene.yaml}", "--out", "same.png", "--labels", "same.png"],
    ["mmd", "{tiny.png}", "{tiny.png}"],
    ["mmd", "{real.png}", "{synth.png}"],
    # issue 21
    ["trace", "stats", "/dev/zero"],
    ["trace", "html", "/dev/zero"],
    ["rules", "run", "/dev/zero"],
    ["check", "/dev/zero"],
    ["run", "{scene.yaml}", "--seed", "-1"],
    ["run", "{scene.yaml}", "--out", ""],
    ["sweep", "{scene.yaml}", "--out", ""],
    ["check", "{scene.yaml}", "--set", "run..fps=3"],
    ["sweep", "{scene.yaml}", "--workers", "64"],
    ["run", "{textured.yaml}", "--out", "inputs", "--no-video"],
    ["render", "{textured.yaml}", "--out", "inputs/figures/floor.png"],
    ["sweep", "{textured.yaml}", "--out", "inputs", "--workers", "1"],
    ["rules", "run", "{sources.soar}", "--trace", "{perception.soar}"],
])
def test_the_reported_command_lines(pool: Pool, argv: list[str]) -> None:
    refused = {"nosuch", "Z99", "-5", "{wj.soar}", "", "--nosuch", "{wj5.jsonl}", "1e9", "100000000",
               "same.png", "{tiny.png}", "{synth.png}", "/dev/zero", "-1", "run..fps=3", "64",
               "inputs", "inputs/figures/floor.png", "{perception.soar}"} & set(argv[2:] + argv[:1])
    argv = [pool.path(a[1:-1]) if a.startswith("{") else a for a in argv]
    outcome = run_checked(pool, argv)
    if refused:
        assert outcome.status != 0, outcome
