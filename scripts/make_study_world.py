#!/usr/bin/env python3
"""Writes configs/worlds/study2018.json, the map of the 2018 user studies (core-language §10),
as a protocol world object taken from the corpus (worlds.jsonl, world_id wdd05b0e5ff41), and
checks it against the description in §10.

Usage: scripts/make_study_world.py [WORLDS_JSONL] [OUT]"""
import json
import sys

WORLD_ID = "wdd05b0e5ff41"
src = sys.argv[1] if len(sys.argv) > 1 else "data/study2018/dev/worlds.jsonl"
out = sys.argv[2] if len(sys.argv) > 2 else "configs/worlds/study2018.json"

rec = next(w for w in map(json.loads, open(src)) if w["world_id"] == WORLD_ID)
world = {k: rec[k] for k in ("walls", "items", "robot", "rooms", "bounds")}

# §10, spelled out.
walls = set()
for y in range(-1, 10):
    walls |= {(-1, y), (12, y)}
for x in range(-1, 13):
    walls |= {(x, -1), (x, 9)}
walls |= {(6, 7), (6, 8), (8, 1)}
walls |= {(x, 6) for x in [0, 1, 2, 3, 4, 6, 7, 8, 10, 11]}
walls |= {(x, 3) for x in range(8, 12)}
walls |= {(x, 2) for x in range(2, 9)}
assert {tuple(w) for w in world["walls"]} == walls, "walls differ from §10"
items = sorted((i["x"], i["y"], i["color"], i["shape"]) for i in world["items"])
expected_items = sorted([
    (3, 8, "blue", "circle"), (3, 8, "yellow", "square"), (10, 8, "green", "triangle"),
    (10, 8, "red", "triangle"), (7, 4, "red", "circle"), (7, 4, "blue", "circle"),
    (7, 4, "green", "square"), (7, 4, "green", "circle"), (4, 0, "red", "triangle"),
    (4, 0, "yellow", "triangle"), (11, 1, "blue", "square")])
assert items == expected_items, "items differ from §10"
box = lambda xs, ys: {(x, y) for x in xs for y in ys}
rooms = {
    "room1": box(range(9, 12), range(0, 3)),
    "room2": box(range(0, 8), range(0, 2)),
    "room3": box(range(0, 8), range(3, 6)) | box(range(8, 12), range(4, 6)),
    "room4": box(range(0, 6), range(7, 9)),
    "room5": box(range(7, 12), range(7, 9)),
}
got_rooms = {k: {tuple(p) for p in v} for k, v in world["rooms"].items()}
# A room is the cells named in §10 that are free (the corpus lists no wall cells in rooms).
for name, cells in rooms.items():
    assert got_rooms[name] == cells - walls, f"{name} differs from §10"
assert set(got_rooms) == set(rooms)
assert world["robot"] == {"x": 2, "y": 4, "holding": []}
assert world["bounds"] == {"min": [-1, -1], "max": [12, 9]}

with open(out, "w") as f:
    f.write("{\n")
    f.write(' "bounds": ' + json.dumps(world["bounds"]) + ",\n")
    f.write(' "robot": ' + json.dumps(world["robot"]) + ",\n")
    f.write(' "items": [\n  ' + ",\n  ".join(json.dumps(i) for i in world["items"]) + "\n ],\n")
    f.write(' "rooms": {\n  ' + ",\n  ".join(
        json.dumps(k) + ": " + json.dumps(v) for k, v in world["rooms"].items()) + "\n },\n")
    f.write(' "walls": ' + json.dumps(world["walls"]) + "\n}\n")
print(f"wrote {out}: {len(world['walls'])} walls, {len(world['items'])} items, rooms {sorted(world['rooms'])}")
