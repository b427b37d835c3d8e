"""Part catalogues: a directory or an archive (zip, tar, tar.gz) of part files, read in
memory — an archive is never extracted, so no member name can reach the disk.

A file that cannot be read becomes a part with an error (the rest of the batch goes
on); a drawing sheet with several parts becomes one item per part (``FILE#K``); too many
parts or too many bytes refuse the whole catalogue.
"""

from __future__ import annotations

import hashlib
import io
import json
import lzma
import tarfile
import zipfile
import zlib
from collections.abc import Iterator
from pathlib import Path, PurePosixPath
from typing import Any

from algrasp.errors import AlgraspError, LimitExceededError, PartDocumentError
from algrasp.io.cad.readers import PART_SUFFIXES, supported

Entry = tuple[str, dict[str, Any], dict[str, Any] | None]  # (name, document, error or None)
"""Part files a catalogue may hold: part documents and CAD files (imported with default
options: every DXF layer, every SVG shape, a mesh's most probable pose)."""


def _entries(filename: str, data: bytes) -> list[Entry]:
    """The catalogue items of one file: a DXF/SVG sheet gives one item per part
    (``FILE#K``), anything else one item (with its error if it cannot be read)."""
    from algrasp.io.cad import import_all_parts, is_cad
    from algrasp.io.parts import parse_part_json

    stem = PurePosixPath(filename).stem
    try:
        docs = import_all_parts(filename, data) if is_cad(filename) else [parse_part_json(data, filename)]  # bounded as over HTTP
    except AlgraspError as exc:
        return [(stem, {}, exc.to_dict())]
    out: list[Entry] = []
    for doc in docs:
        if not isinstance(doc.get("name"), str):
            doc = {**doc, "name": stem}
        out.append((str(doc["name"]), doc, None))
    return out


MAX_MEMBERS = 100_000
"""Most entries (files, directories, links) an archive may list."""


def _members(data: bytes, max_bytes: int) -> Iterator[tuple[str, int, Any]]:
    """(name, size, reader) of each regular file of a zip or tar archive. A tar is read
    member by member: a member declared larger than ``max_bytes`` stops the listing
    before its content is decompressed (a 5 GiB member in a 4 KB tar.bz2)."""
    if zipfile.is_zipfile(io.BytesIO(data)):
        zf = zipfile.ZipFile(io.BytesIO(data))
        infos = zf.infolist()
        if len(infos) > MAX_MEMBERS:
            raise LimitExceededError("archive", f"more than {MAX_MEMBERS} entries")
        for info in infos:
            if info.flag_bits & 0x1 and info.filename.lower().endswith(PART_SUFFIXES):  # open() would raise RuntimeError
                raise PartDocumentError("archive", f"member {_text(info.filename)!r} is encrypted: send an archive "
                                        "without a password")
            if not info.is_dir():
                yield _text(info.filename), info.file_size, lambda i=info: _bounded(zf.open(i), max_bytes)
        return
    try:
        tf = tarfile.open(fileobj=io.BytesIO(data), mode="r:*")  # noqa: SIM115 - read lazily by the caller
    except tarfile.TarError:
        raise PartDocumentError("archive", "not a zip or tar archive") from None
    for n, m in enumerate(iter(tf.next, None)):
        if n >= MAX_MEMBERS:
            raise LimitExceededError("archive", f"more than {MAX_MEMBERS} entries")
        if m.isfile():
            if m.size > max_bytes:
                raise LimitExceededError("archive", f"member {_text(m.name)!r} declares {m.size} bytes (at most "
                                         f"{max_bytes})")
            yield _text(m.name), m.size, lambda m=m: _bounded(tf.extractfile(m), max_bytes)


def _text(name: str) -> str:
    """A member name as valid text (tar names that are not UTF-8 come with surrogates)."""
    return name.encode("utf-8", "replace").decode("utf-8")


def _bounded(stream: Any, max_bytes: int) -> bytes:
    """At most ``max_bytes`` of a member, whatever its header claims."""
    data: bytes = stream.read(max_bytes + 1)
    if len(data) > max_bytes:
        raise LimitExceededError("archive", f"a member holds more than {max_bytes} bytes")
    return data


def read_archive(data: bytes, max_parts: int, max_bytes: int) -> list[Entry]:
    """The part files of an archive, sorted by name; other files are skipped. A damaged
    archive is one PartDocumentError; a damaged member is that member's error."""
    return read_archive_said(data, max_parts, max_bytes)["entries"]  # type: ignore[no-any-return]


def read_archive_said(data: bytes, max_parts: int, max_bytes: int) -> dict[str, Any]:
    """:func:`read_archive` as ``{"entries", "skipped"}``: with the files it skipped and why
    (``"notes.txt: not a part file"``). A dict: a worker's tuple is a run's (response, run, error)."""
    try:
        entries, skipped = _read_archive(data, max_parts, max_bytes)
        return {"entries": entries, "skipped": skipped}
    except (zipfile.BadZipFile, tarfile.TarError, EOFError, zlib.error, lzma.LZMAError, OSError, ValueError,
            NotImplementedError) as exc:  # truncated, corrupt or unsupported compression
        raise PartDocumentError("archive", f"damaged archive ({type(exc).__name__}: {str(exc)[:200]})") from None


def _read_archive(data: bytes, max_parts: int, max_bytes: int) -> tuple[list[Entry], list[str]]:
    out: list[Entry] = []
    skipped: list[str] = []
    total = 0
    for name, size, read in sorted(_members(data, max_bytes), key=lambda m: m[0]):
        if PurePosixPath(name).name.startswith("."):
            skipped.append(f"{name}: a hidden file")
            continue
        if not name.lower().endswith(PART_SUFFIXES):
            skipped.append(f"{name}: not a part file ({supported()})")
            continue
        total += size
        if total > max_bytes:  # checked on the declared sizes, before decompressing (zip bombs)
            raise LimitExceededError("archive", f"more than {max_bytes} bytes of part files")
        if len(out) >= max_parts:
            raise LimitExceededError("archive", f"more than {max_parts} part files")
        out += _entries(PurePosixPath(name).name, read())
        if len(out) > max_parts:
            raise LimitExceededError("archive", f"more than {max_parts} parts (part files and the parts on their sheets)")
    if not out:
        raise PartDocumentError("archive", f"no part files ({supported()}) in the archive")
    return out, skipped


def read_catalogue(path: Path, max_parts: int, max_bytes: int) -> list[Entry]:
    """A catalogue directory (its part files, recursively) or archive file."""
    if path.is_file():
        return read_archive(path.read_bytes(), max_parts, max_bytes)
    if not path.is_dir():
        raise PartDocumentError("CATALOGUE", f"no such directory or archive: {path}")
    files = sorted(p for p in path.rglob("*") if p.is_file() and p.suffix.lower() in PART_SUFFIXES)
    if not files:
        raise PartDocumentError("CATALOGUE", f"no part files ({supported()}) in {path}")
    if len(files) > max_parts:
        raise LimitExceededError("CATALOGUE", f"more than {max_parts} part files")
    out = [e for p in files for e in _entries(p.name, p.read_bytes())]
    if len(out) > max_parts:
        raise LimitExceededError("CATALOGUE", f"more than {max_parts} parts (part files and the parts on their sheets)")
    return out


def catalogue_hash(entries: list[Entry], options: dict[str, Any]) -> str:
    """Canonical hash of a catalogue and its options (the batch CLI resumes a job by it)."""
    return canonical_hash({"parts": [[n, d, e] for n, d, e in entries], "options": options})


def canonical_hash(value: Any) -> str:
    """SHA-256 of the canonical JSON of ``value`` (sorted keys, no spaces)."""
    return hashlib.sha256(json.dumps(value, sort_keys=True, separators=(",", ":")).encode()).hexdigest()
