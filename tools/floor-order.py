#!/usr/bin/env python3
"""Lists the files of the library that include a header from a higher floor.

    tools/floor-order.py [root]   (default: the repository this script is in)

The library's folders (rooms) stand on floors, lowest first; a file may include
headers of its own room and of rooms on lower floors, never of a room on its
own floor or above it:

    core, geometry   the engine's basics; analytic shapes and triangles
    levelset         the level-set engine
    scan             range maps and the data term drawn from them
    io, synth        files in and out; generated scenes and their range maps
    recon            the reconstruction
    mpi              the reconstruction over MPI ranks
    python           the Python module

io's rooms stand on floors of their own: the shared basics directly in io/,
then images/ and vdb/, then scans/ and outputs/. A room is a folder of
src/ (its sources and private headers) and of include/levelfuse/ (its public
headers, a detail/ folder in it included); a private header is found by its path
from the including file.
Exits 1 if a file includes a header from its own floor's other rooms or from a
higher floor, or if a file lies in a folder that stands on no floor.
"""
import os
import pathlib
import re
import sys

FLOORS = [
    ["core", "geometry"],
    ["levelset"],
    ["scan"],
    ["io", "synth"],
    ["recon"],
    ["mpi"],
    ["python"],
]
# The floors inside a room, lowest first ("" is the room's own folder).
INNER_FLOORS = {
    "io": [[""], ["images", "vdb"], ["scans", "outputs"]],
}
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^">]+)[">]', re.M)


def room_of(root, path):
    """The room a file of src/ or include/levelfuse/ is in ("io/scans"), "" for
    the umbrella header directly in include/levelfuse, or None outside them."""
    parts = path.relative_to(root).parts
    if parts[:2] == ("include", "levelfuse"):
        folders = parts[2:-1]
    elif parts[0] == "src" and len(parts) > 2:
        folders = parts[1:-1]
    else:
        return None
    if folders[-1:] == ("detail",):  # a room's implementation details are part of it
        folders = folders[:-1]
    return "/".join(folders)


def level(room):
    """Where a room stands: (floor, its room's name, floor inside that room), or None if nowhere."""
    top, _, inner = room.partition("/")
    for floor, rooms in enumerate(FLOORS):
        if top in rooms:
            break
    else:
        return None
    if top not in INNER_FLOORS:
        return (floor, top, 0) if not inner else None
    for inner_floor, inner_rooms in enumerate(INNER_FLOORS[top]):
        if inner in inner_rooms:
            return (floor, top, inner_floor)
    return None


def may_include(room, target_room):
    """Whether a file of `room` may include a header of `target_room`."""
    if room == target_room:
        return True
    mine, theirs = level(room), level(target_room)
    if mine[1] == theirs[1]:
        return mine[2] > theirs[2]
    return mine[0] > theirs[0]


def placement(room, target_room):
    """How a room stands to one it may not include: "below" or "beside"."""
    mine, theirs = level(room), level(target_room)
    same_floor = mine[2] == theirs[2] if mine[1] == theirs[1] else mine[0] == theirs[0]
    return "beside" if same_floor else "below"


def violations(root):
    """(file, included header, why) for every include that reaches up or sideways."""
    found = []
    paths = sorted(list((root / "include/levelfuse").rglob("*.h")) + list((root / "src").rglob("*.cc")) +
                   list((root / "src").rglob("*.h")))
    for path in paths:
        room = room_of(root, path)
        rel = path.relative_to(root)
        if room == "":
            continue  # the umbrella header includes every room
        if room is None or level(room) is None:
            found.append((rel, "", f"its folder {rel.parent} stands on no floor (add it to tools/floor-order.py)"))
            continue
        for bracket, target in INCLUDE.findall(path.read_text(errors="replace")):
            if target.startswith("levelfuse/"):
                header = root / "include" / target
            elif bracket == '"':
                header = pathlib.Path(os.path.normpath(path.parent / target))
            else:
                continue
            if not header.is_relative_to(root) or not header.exists():
                continue  # a generated header (Version.h) or one outside the library
            target_room = room_of(root, header)
            if target_room is None:
                continue
            if target_room == "":
                found.append((rel, target, "the umbrella header includes every floor"))
            elif level(target_room) is None:
                continue  # reported as its own file
            elif not may_include(room, target_room):
                found.append((rel, target, f"{room} stands {placement(room, target_room)} {target_room}"))
    return found


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
    found = violations(root)
    for rel, target, why in found:
        print(f"{rel}: {target + ': ' if target else ''}{why}")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
