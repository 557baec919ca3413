"""LALR parsers for the grammars shipped in `symsynth.grammars`, their
tables built once and then read from symsynth's cache directory.

Building an LALR parser's tables is lark's grammar analysis: 30-35 ms for
the LTLf grammar (a sixth of a whole `symsynth dfa` run), 0.3 s for TLSF's;
reading them back takes 3 ms.  They are kept in a file of
`files.cache_dir()` (the user's own directory: not a shared /tmp, where
another user could plant the pickle read back) named by a digest of the
grammar, its options, lark's version and Python's.  The file's first line
is the SHA-256 of the rest, lark's saved parser: a file that does not match
it (cut short, spoilt) is ignored, and the tables are built and written again.

A file is written whole or not at all (`files.write_atomic`: a temporary
file renamed over it), so processes starting at once never read one half
written: each reads a whole file or builds the tables itself.  (Lark's own
`cache=` option writes in place, and two builds of the same grammar need
not give the same bytes: a reader could see a mix.)  A folder that cannot
be made or written costs time only: the tables are built in every run,
and nothing is reported.
"""

from __future__ import annotations

import hashlib
import io
import sys
from pathlib import Path
from typing import Any

import lark

from symsynth.errors import InputError
from symsynth.files import cache_dir, write_atomic


def grammar_text(name: str) -> str:
    """`grammars/NAME` from the installed package data, or from the source
    tree when symsynth is imported from a checkout without installing.
    (The package's folder, not `importlib.resources`, which imports its
    readers and zipfile for this: 2-4 ms of every start at load 4.)"""
    try:
        import symsynth.grammars  # type: ignore[import-untyped]  # (grammars/, mapped into the package)
        folder = Path(symsynth.grammars.__file__).parent
    except ModuleNotFoundError:
        folder = Path(__file__).resolve().parents[2] / "grammars"
    return (folder / name).read_text(encoding="utf-8")


def lalr_parser(name: str, **options: Any) -> lark.Lark:
    """The LALR parser of `grammars/NAME` with lark's `options` (a
    `transformer` among them is applied as it parses)."""
    text = grammar_text(name)
    path = table_file(name, text, options)
    payload = None if path is None else read_tables(path)
    if payload is not None:
        # what lark's own cache= does with the tables it reads back: the
        # transformer is not in the file, it is given here
        parser = lark.Lark.__new__(lark.Lark)
        return parser._load(io.BytesIO(payload), transformer=options.get("transformer"))
    parser = lark.Lark(text, parser="lalr", **options)
    if path is not None:
        saved = io.BytesIO()
        parser.save(saved, exclude_options=("transformer",))
        digest = hashlib.sha256(saved.getvalue()).hexdigest()
        try:
            write_atomic(path, digest.encode("ascii") + b"\n" + saved.getvalue(), "parser tables")
        except InputError:
            pass  # (a folder that cannot be written: built again next time)
    return parser


def table_file(name: str, text: str, options: dict[str, Any]) -> Path | None:
    """Where the tables of grammar `name` (its `text`) are kept, or None
    (build them every time) when the cache folder cannot be made."""
    folder = cache_dir()
    try:
        folder.mkdir(parents=True, exist_ok=True, mode=0o700)
    except OSError:
        return None
    settings = sorted((k, repr(v)) for k, v in options.items() if k != "transformer")
    key = repr((text, settings, lark.__version__, sys.version_info[:2]))
    return folder / f"{Path(name).stem}-lalr-{hashlib.sha256(key.encode('utf-8')).hexdigest()[:20]}.cache"


def read_tables(path: Path) -> bytes | None:
    """The saved parser in `path`, None when there is none whole."""
    try:
        digest, _, payload = path.read_bytes().partition(b"\n")
    except OSError:
        return None
    return payload if hashlib.sha256(payload).hexdigest().encode("ascii") == digest else None
