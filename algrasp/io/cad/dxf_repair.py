"""Repairs of DXF text that ezdxf refuses but AutoCAD-family readers take.

- **LWPOLYLINEs without subclass markers** (OpenJsCad writes them so, with no header and
  a Z code per vertex): ezdxf needs ``100 AcDbEntity`` / ``100 AcDbPolyline`` to tell the
  entity's common attributes from the polyline's. The markers are put where AutoCAD writes
  them, the Z codes (not part of an LWPOLYLINE: its elevation is code 38) dropped, and a
  file that names no version is declared R2000 (an LWPOLYLINE is R14 or later).
"""

from __future__ import annotations

Tag = tuple[str, str]

COMMON_CODES = frozenset({"5", "330", "102", "360"})
"""Tags before the first subclass marker: handle, owner, reactor and dictionary groups."""
POLYLINE_CODES = frozenset({"90", "70", "43", "38", "39", "10"})
"""The first tag of an LWPOLYLINE's own subclass (AcDbPolyline) is one of these."""
ASSUMED_VERSION = "AC1015"
"""The version declared for a file with LWPOLYLINEs that names none (R2000)."""


def _pairs(text: str) -> list[Tag] | None:
    """The (code, value) tags of a DXF text, or None when it is not a sequence of pairs."""
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    if len(lines) % 2:
        return None
    pairs = [(lines[i].strip(), lines[i + 1]) for i in range(0, len(lines), 2)]
    return pairs if all(c.lstrip("-").isdigit() for c, _ in pairs) else None


def _marked(body: list[Tag]) -> list[Tag]:
    """An LWPOLYLINE's tags (after its ``0 LWPOLYLINE``) with subclass markers."""
    if any(c == "100" for c, _ in body):
        return body
    head = [t for t in body if t[0] in COMMON_CODES]
    rest = [t for t in body if t[0] not in COMMON_CODES]
    k = next((n for n, t in enumerate(rest) if t[0] in POLYLINE_CODES), len(rest))
    own = [t for t in rest[k:] if t[0] != "30"]
    return [*head, ("100", "AcDbEntity"), *rest[:k], ("100", "AcDbPolyline"), *own]


def _with_version(tags: list[Tag]) -> list[Tag]:
    """Tags whose header names a version: R2000 put first in the header (or in a new
    header section) when it names none."""
    if any(c == "9" and v.strip() == "$ACADVER" for c, v in tags):
        return tags
    version = [("9", "$ACADVER"), ("1", ASSUMED_VERSION)]
    for n in range(len(tags) - 1):
        if tags[n] == ("0", "SECTION") and tags[n + 1][0] == "2" and tags[n + 1][1].strip() == "HEADER":
            return [*tags[:n + 2], *version, *tags[n + 2:]]
    start = next((n for n, t in enumerate(tags) if t == ("0", "SECTION")), 0)
    return [*tags[:start], ("0", "SECTION"), ("2", "HEADER"), *version, ("0", "ENDSEC"), *tags[start:]]


def lwpolyline_markers(text: str) -> str | None:
    """The text with subclass markers added to its LWPOLYLINEs (see module docs), or None
    when none lacks them (or the text is not tag pairs)."""
    if "LWPOLYLINE" not in text or "AcDbPolyline" in text:
        return None
    tags = _pairs(text)
    if tags is None:
        return None
    out: list[Tag] = []
    n = 0
    while n < len(tags):
        out.append(tags[n])
        n += 1
        if out[-1][0] == "0" and out[-1][1].strip() == "LWPOLYLINE":
            end = next((m for m in range(n, len(tags)) if tags[m][0] == "0"), len(tags))
            out += _marked(tags[n:end])
            n = end
    return "".join(f"{c}\n{v}\n" for c, v in _with_version(out))
