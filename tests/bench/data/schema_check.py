#!/usr/bin/env python3
"""Test program for the external protocol: validates each request grapebench sends
against docs/external-protocol.schema.json (python3-jsonschema), checks that the
files it names hold what it says, and answers 1 mm / 1 mm3 per quantity, or equal class scores for a
classification request (its answer validated too). Usage: schema_check.py SCHEMA [--persistent | REQUEST]."""
import json
import sys

import jsonschema


def check(schema, req):
    jsonschema.validate(req, {"$ref": "#/$defs/request", "$defs": schema["$defs"]})
    with open(req["cloud"], "rb") as f:
        head = f.read(4096).split(b"end_header\n")[0].decode("ascii")
    if "element vertex %d\n" % req["points"] not in head:
        raise ValueError("the cloud's header does not hold %d points" % req["points"])
    for a, prop in (("normals", "nx"), ("viewpoints", "vx"), ("colours", "red")):
        if (a in req.get("attributes", [])) != ("property" in head and (" %s\n" % prop) in head):
            raise ValueError("attribute %s and the PLY header disagree" % a)
    if "stereo" in req:
        for side in ("left", "right"):
            with open(req["stereo"][side], "rb") as f:
                if f.read(8) != b"\x89PNG\r\n\x1a\n":
                    raise ValueError("%s: not a PNG file" % req["stereo"][side])
    answer = {q: 1e-9 if q == "volume" else 1e-3 for q in req["quantities"]}
    if req.get("kind") == "classification":
        if len(req["train_labels"]) != req["points"] or "red" not in head:
            raise ValueError("classification: train_labels or the cloud's colours are missing")
        k = len(req["classes"])
        answer["class_scores"] = [[1.0 / k] * k] * req["points"]
    answer["notes"] = "schema ok: %s %s" % (req["protocol"], req.get("kind", ""))
    jsonschema.validate(answer, {"$ref": "#/$defs/answer", "$defs": schema["$defs"]})
    return answer


def main():
    with open(sys.argv[1]) as f:
        schema = json.load(f)
    if sys.argv[2] == "--persistent":
        for line in sys.stdin:
            try:
                reply = check(schema, json.loads(line))
            except Exception as e:  # noqa: BLE001 - the harness fails the row with it
                reply = {"error": str(e)}
            print(json.dumps(reply), flush=True)
        return
    with open(sys.argv[2]) as f:
        req = json.load(f)
    try:
        reply = check(schema, req)
    except Exception as e:  # noqa: BLE001
        sys.exit("schema check failed: %s" % e)
    with open(req["answer"], "w") as f:
        json.dump(reply, f)


if __name__ == "__main__":
    main()
