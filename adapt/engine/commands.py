"""The commands of Soar agent files: which adapt accepts, and what each means.

Soar reads a ``.soar`` file as a script of commands, split into words by its
own Tcl-like tokenizer (``Core/shared/tokenizer.h``): commands end at a
newline or ``;``; ``{...}`` (braces nest) and ``"..."`` group words; ``#``
at the start of a command, or starting a word, comments out the rest of the
line; a backslash escapes the next character.  ``sp {...}`` adds a production
and every other line is a command.  :func:`read_command` splits one command
the same way; :func:`interpret` says what adapt does with it:

=====================================  ==============================================
command (and its Soar aliases)         adapt
=====================================  ==============================================
``source FILE``                        reads FILE, relative to the current directory
                                       of the reading, which ``FILE``'s own directory
                                       becomes while it is read (as in Soar)
``pushd DIR``, ``popd``                change that directory (a stack)
``srand N`` (``decide srand N``)       seeds the agent: operator selection and
                                       ``rand-int`` / ``rand-float``
``multi-attributes ATTR [N]``          a hint to condition reordering: ``^ATTR``
(``production optimize-attribute``)    has about N values (default 10)
``chunk never`` / ``chunk off`` /      accepted: learning is off, which is all adapt
``learn --off`` / ``learn -d``         does
``watch``, ``w``, ``trace`` (any       accepted and ignored: they choose what Soar
level or category)                     prints, not what the agent does
``echo TEXT``                          a message of the agent (``Agent.messages``)
``max-elaborations N``,                the agent's ``max_elaborations`` /
``max-goal-depth N`` (``soar ...``)    ``max_goal_depth``
``output agent-writes on|off``         whether ``(write ...)`` output is kept
``output warnings on|off``             accepted and ignored (printing only)
``soar wait-snc off`` (``waitsnc       accepted: Soar's default, the only behaviour
--off``), ``wma -s activation off``    adapt has (state no-change impasses are made;
                                       no working-memory activation)
=====================================  ==============================================

Everything else is refused with a positioned
:class:`~adapt.errors.RuleSemanticError` that names the command and the Soar
engine, which runs it (``--engine soar``, :mod:`adapt.soar`), and nothing
is executed: chunking other than ``never`` (``chunk always``, ``learn --on``,
chunking settings), reinforcement learning (``rl``), semantic and episodic
memory (``smem``, ``epmem``), ``gp``, and any other Soar command.  With
``chunking="off"`` (an agent written for chunking, run with learning off) the
chunking commands and settings are accepted and ignored instead.

Examples
--------
>>> cmd = read_command('source "my agent.soar" # the rest', 0)
>>> cmd.words, cmd.end
(('source', 'my agent.soar'), 33)
>>> interpret(read_command("multi-attributes holds 8", 0))
Setting(kind='multi-attributes', name='holds', value=8)
>>> interpret(read_command("chunk always", 0))
Traceback (most recent call last):
  ...
adapt.engine.commands.Refusal: 'chunk always' turns chunking on, which adapt does not implement; remove the line, write 'chunk never', or run it on the Soar engine (--engine soar)
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Literal, Union

__all__ = ["Command", "Setting", "Source", "Pushd", "Popd", "Refusal", "CommandSyntaxError",
           "read_command", "skip_blank", "interpret", "Chunking", "ON_SOAR"]

#: The end of every refusal of something the Soar engine runs (chunking, RL, smem, ...).
ON_SOAR = "run it on the Soar engine (--engine soar)"

#: What agent-file commands about chunking do: ``"refuse"`` (the default:
#: anything that would turn learning on is an error) or ``"off"`` (an agent
#: written for chunking runs with learning off: those commands are ignored).
Chunking = Literal["refuse", "off"]

_BLANK = re.compile(r"(?:[\s;]+|#[^\n]*)*")
_ESCAPES = {"a": "\a", "b": "\b", "f": "\f", "n": "\n", "r": "\r", "t": "\t", "v": "\v"}


class CommandSyntaxError(Exception):
    """A command that cannot be split into words (an unterminated ``{`` or ``"``)."""

    def __init__(self, message: str, offset: int) -> None:
        super().__init__(message)
        self.message = message
        self.offset = offset


class Refusal(Exception):
    """A command adapt does not run; ``word`` is the index of the word to point at;
    ``unknown``: the first word is not a Soar command at all."""

    def __init__(self, message: str, word: int = 0, unknown: bool = False) -> None:
        super().__init__(message)
        self.message = message
        self.word = word
        self.unknown = unknown


@dataclass(frozen=True, slots=True)
class Command:
    """One command of an agent file: its words and where each starts."""

    words: tuple[str, ...]
    starts: tuple[int, ...]
    end: int


@dataclass(frozen=True, slots=True)
class Setting:
    """An accepted command that sets something on the agent.

    ``kind`` is ``seed``, ``multi-attributes``, ``max-elaborations``,
    ``max-goal-depth``, ``agent-writes``, ``echo`` or ``symbols`` (a word
    Soar's symbol table gets from an ignored command: only the order of
    constants sees it); ``name`` is the attribute of a ``multi-attributes``
    hint.
    """

    kind: str
    name: str | None = None
    value: Union[int, str, bool, None] = None


@dataclass(frozen=True, slots=True)
class Source:
    """``source PATH``."""

    path: str


@dataclass(frozen=True, slots=True)
class Pushd:
    """``pushd DIR``."""

    path: str


@dataclass(frozen=True, slots=True)
class Popd:
    """``popd``."""


#: What :func:`interpret` makes of a command (``None``: accepted, nothing to do).
Meaning = Union[Setting, Source, Pushd, Popd, None]


def skip_blank(text: str, pos: int) -> int:
    """The offset of the next command's first character (or ``len(text)``):
    white space, ``;`` and ``#`` comments are skipped."""
    m = _BLANK.match(text, pos)
    return m.end() if m is not None else pos


def read_command(text: str, pos: int) -> Command:
    """Split the command starting at ``pos`` into words, as Soar's tokenizer does.

    Raises
    ------
    CommandSyntaxError
        For an unterminated ``{`` or ``"`` (``offset`` is where it opened).
    """
    n = len(text)
    words: list[str] = []
    starts: list[int] = []
    i = pos
    while i < n:
        c = text[i]
        if c == "\n" or c == ";":
            i += 1
            break
        if c.isspace():
            i += 1
            continue
        if c == "#":
            end = text.find("\n", i)
            i = n if end < 0 else end
            continue
        starts.append(i)
        if c == '"':
            word, i = _quoted(text, i)
        elif c == "{":
            word, i = _braced(text, i)
        else:
            word, i = _plain(text, i)
        words.append(word)
    return Command(tuple(words), tuple(starts), i)


def _escape(text: str, i: int) -> tuple[str, int]:
    """The character a backslash at ``i`` stands for, and the offset after it."""
    if i + 1 >= len(text):
        return "", i + 1
    c = text[i + 1]
    if c == "\n":  # backslash-newline and the following blanks: one space
        j = i + 2
        while j < len(text) and text[j] in " \t":
            j += 1
        return " ", j
    return _ESCAPES.get(c, c), i + 2


def _quoted(text: str, start: int) -> tuple[str, int]:
    out: list[str] = []
    i = start + 1
    while True:
        if i >= len(text):
            raise CommandSyntaxError('unterminated quoted word: no closing \'"\'', start)
        c = text[i]
        if c == '"':
            return "".join(out), i + 1
        if c == "\\":
            ch, i = _escape(text, i)
            out.append(ch)
            continue
        out.append(c)
        i += 1


def _braced(text: str, start: int) -> tuple[str, int]:
    """A ``{...}`` word: braces nest, ``#`` comments out the rest of a line
    (except between ``|`` bars), ``\\`` keeps the next character."""
    out: list[str] = []
    depth = 1
    literal = False
    i = start + 1
    n = len(text)
    while True:
        if i >= n:
            raise CommandSyntaxError("unterminated '{': no matching '}'", start)
        c = text[i]
        i += 1
        if c == "\\" and i < n:
            out.append(c + text[i])
            i += 1
            continue
        if c == "#" and not literal:
            end = text.find("\n", i)
            i = n if end < 0 else end
            continue
        if not literal:
            if c == "{":
                depth += 1
            elif c == "}":
                depth -= 1
                if depth == 0:
                    return "".join(out), i
        out.append(c)
        if c == "|":
            literal = not literal


def _plain(text: str, start: int) -> tuple[str, int]:
    out: list[str] = []
    i = start
    n = len(text)
    while i < n:
        c = text[i]
        if c.isspace() or c == ";":
            break
        if c == "#":
            end = text.find("\n", i)
            return "".join(out), (n if end < 0 else end)
        if c == "\\":
            ch, i = _escape(text, i)
            out.append(ch)
            continue
        out.append(c)
        i += 1
    return "".join(out), i


# -- meaning --------------------------------------------------------------------------

_OFF_WORDS = frozenset({"never", "off", "--off", "-d", "--disable", "disable"})
_CHUNK_COMMANDS = frozenset({"chunk", "learn"})
_NOT_IMPLEMENTED = {
    "rl": "reinforcement learning is not implemented",
    "smem": "semantic memory is not implemented",
    "epmem": "episodic memory is not implemented",
    "svs": "the spatial visual system is not implemented",
    "wma": "working-memory activation is not implemented",
    "gp": "generated productions are not supported; write each production with sp",
    "indifferent-selection": "only Soar's default selection policy (softmax) is implemented",
    "numeric-indifferent-mode": "only Soar's default numeric-indifferent mode (sum) is "
                                "implemented",
}
_ALIASES = {"w": ("trace",), "watch": ("trace",), "srand": ("decide", "srand"),
            "multi-attributes": ("production", "optimize-attribute"),
            "max-elaborations": ("soar", "max-elaborations"),
            "max-goal-depth": ("soar", "max-goal-depth"),
            "inds": ("decide", "indifferent-selection"),
            "indifferent-selection": ("decide", "indifferent-selection"),
            "numeric-indifferent-mode": ("decide", "numeric-indifferent-mode")}


#: Soar 9.6's commands and aliases (``cli_CommandLineInterface``, ``cli_Aliases.h``).
SOAR_COMMANDS: frozenset[str] = frozenset((
    "alias chunk cd debug decide dirs echo epmem explain gp help learn load ls output popd "
    "preferences print production pushd pwd rl run save smem soar source sp stats svs trace "
    "visualize wm version exit quit "
    "a aw chdir ctf d dir e ex fc gds_print inds init interrupt is man p pc ps pw r rn rw s "
    "set-default-depth ss st step stop topd un varprint w wmes cs c ef ei es i wt et unalias "
    "indifferent-selection numeric-indifferent-mode predict select srand replay-input rete-net "
    "load-library capture-input pbreak excise production-find firing-counts matches memories "
    "multi-attributes pwatch add-wme wma remove-wme watch-wmes allocate internal-symbols port "
    "time init-soar stop-soar gp-max max-dc-time max-elaborations max-goal-depth "
    "max-memory-usage max-nil-output-cycles set-stop-phase soarnews cli tcl timers waitsnc "
    "chunk-name-format max-chunks clog command-to-file default-wme-depth echo-commands verbose "
    "warnings watch o-support-mode save-backtraces sp-local set-parameter"
).split())


def _int_word(words: tuple[str, ...], k: int, what: str, minimum: int) -> int:
    if k >= len(words):
        raise Refusal(f"'{' '.join(words)}' needs {what}", 0)
    try:
        value = int(words[k])
    except ValueError:
        raise Refusal(f"{what} must be an integer, not {words[k]!r}", k) from None
    if value < minimum:
        raise Refusal(f"{what} must be at least {minimum}, not {value}", k)
    return value


def _on_off(words: tuple[str, ...], k: int) -> bool:
    if k < len(words) and words[k] in ("on", "off"):
        return words[k] == "on"
    raise Refusal(f"'{' '.join(words[:k])}' takes 'on' or 'off'", min(k, len(words) - 1))


def _is_default_off(canonical: tuple[str, ...]) -> bool:
    """``soar wait-snc off`` and ``wma -s activation off``: settings that turn
    off what adapt never does (Soar's defaults)."""
    if canonical[:2] in (("soar", "wait-snc"), ("soar", "waitsnc")):
        return canonical[2:] in (("off",), ("--off",), ("-d",), ("--disable",))
    if canonical[0] == "waitsnc":
        return canonical[1:] in (("--off",), ("-d",), ("--disable",))
    if canonical[0] == "wma":
        return canonical[1:] in (("-s", "activation", "off"), ("--set", "activation", "off"))
    return False


def interpret(command: Command, chunking: Chunking = "refuse") -> Meaning:
    """What adapt does with one (non-``sp``) command of an agent file.

    Raises
    ------
    Refusal
        For every command adapt does not accept (see the module docstring).
    """
    words = command.words
    head = words[0]
    shown = " ".join(words)
    if head in ("decide", "production", "soar") and len(words) > 1:
        canonical = words
    else:
        canonical = _ALIASES.get(head, (head,)) + words[1:]
    name = canonical[0]
    if name == "source":
        args = [w for w in words[1:] if not w.startswith("-")]
        if len(args) != 1:
            raise Refusal("'source' takes one file name (put quotes around a name with "
                          "spaces)", 0)
        return Source(args[0])
    if name == "pushd":
        if len(words) != 2:
            raise Refusal("'pushd' takes one directory", 0)
        return Pushd(words[1])
    if name == "popd":
        if len(words) != 1:
            raise Refusal("'popd' takes no arguments", 1)
        return Popd()
    if name == "echo":
        return Setting("echo", value=" ".join(w for w in words[1:] if w != "--nonewline"))
    if name == "trace":
        return None
    if canonical[:2] == ("decide", "srand"):
        k = len(words) - len(canonical) + 2
        if k >= len(words):
            raise Refusal("'srand' without a seed seeds Soar from the clock, which would make "
                          "the run irreproducible; give a seed ('srand 1')", 0)
        return Setting("seed", value=_int_word(words, k, "the seed", 0))
    if canonical[:2] == ("production", "optimize-attribute"):
        k = len(words) - len(canonical) + 2
        if k >= len(words):
            raise Refusal("'multi-attributes' needs an attribute", 0)
        count = _int_word(words, k + 1, "the number of values", 1) if k + 1 < len(words) else 10
        return Setting("multi-attributes", name=words[k], value=count)
    if canonical[:2] in (("soar", "max-elaborations"), ("soar", "max-goal-depth")):
        k = len(words) - len(canonical) + 2
        return Setting(canonical[1], value=_int_word(words, k, f"the {canonical[1]} limit", 1))
    if name == "output" and len(words) >= 2 and words[1] in ("agent-writes", "warnings"):
        on = _on_off(words, 2)
        return Setting("agent-writes", value=on) if words[1] == "agent-writes" else None
    if _is_default_off(canonical):
        return None
    if name in _CHUNK_COMMANDS:
        if len(words) == 2 and words[1] in _OFF_WORDS:
            return None
        if chunking == "off":
            if len(words) == 5 and words[1] == "singleton":
                # ignored, but Soar makes the attribute's symbol here, which
                # breaks the join order's last ties (reorder.ConstantOrder)
                return Setting("symbols", value=words[3])
            return None
        what = ("turns chunking on" if len(words) == 2 and words[1] in
                ("always", "on", "only", "except", "--on", "-e", "--enable", "enable")
                else "configures chunking")
        raise Refusal(f"'{shown}' {what}, which adapt does not implement; remove the line, "
                      f"write 'chunk never', or {ON_SOAR}", 0)
    why = _NOT_IMPLEMENTED.get(canonical[1] if name == "decide" and len(canonical) > 1
                               else name)
    if why is not None:
        raise Refusal(f"'{head}' is a Soar command adapt does not run ({why}); {ON_SOAR}", 0)
    if head not in SOAR_COMMANDS:
        raise Refusal(f"expected 'sp {{' to begin a production, or an agent-file command, "
                      f"found {head!r}", 0, unknown=True)
    raise Refusal(f"'{shown}' is a Soar command adapt does not run in agent files (besides "
                  "'sp' productions they may hold source, pushd, popd, srand, "
                  "multi-attributes, chunk never, watch, echo, max-elaborations, "
                  f"max-goal-depth and output agent-writes); {ON_SOAR}", 0)
