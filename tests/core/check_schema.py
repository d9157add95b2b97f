#!/usr/bin/python3
"""The shipped JSON Schema agrees with the loader on the examples: valid
blocks validate, and blocks the loader refuses for structural reasons are
refused by the schema too.

    check_schema.py SOURCE_DIR
"""

import copy
import json
import os
import sys

import jsonschema

source = sys.argv[1]
with open(os.path.join(source, "core/io/geostation-block.schema.json")) as f:
    schema = json.load(f)
jsonschema.Draft7Validator.check_schema(schema)
validator = jsonschema.Draft7Validator(schema)

with open(os.path.join(source, "docs/examples/sample.geostation.json")) as f:
    sample = json.load(f)

passed = failed = 0


def expect(doc, valid, what):
    global passed, failed
    errors = list(validator.iter_errors(doc))
    if (not errors) == valid:
        passed += 1
    else:
        failed += 1
        print("FAIL: %s: expected %s, schema said %s" % (what, "valid" if valid else "invalid",
                                                         [e.message for e in errors] or "valid"))


def broken(change):
    doc = copy.deepcopy(sample)
    change(doc)
    return doc


expect(sample, True, "the sample block")
expect(broken(lambda d: d.update(format="other")), False, "wrong format")
expect(broken(lambda d: d.update(version=2)), False, "version 2")
expect(broken(lambda d: d.pop("cameras")), False, "no cameras")
expect(broken(lambda d: d.update(cameras=[])), False, "empty cameras")
expect(broken(lambda d: d["cameras"][0].update(width=640.5)), False, "fractional width")
expect(broken(lambda d: d["cameras"][0].update(f=-1)), False, "negative f")
expect(broken(lambda d: d["cameras"][0]["distortion"].update(model="fisheye")), False, "unknown model")
expect(broken(lambda d: d["cameras"][1].pop("pixel_size_mm")), False, "brown_photo without pixel size")
expect(broken(lambda d: d["stations"][0].update(time="yesterday")), False, "bad time")
expect(broken(lambda d: d["images"][0].pop("kappa")), False, "partial exterior orientation")
expect(broken(lambda d: d["images"][0]["sigma"].update(Z=-1)), False, "negative sigma")
expect(broken(lambda d: d["images"][2].update(sigma={"X": 1, "Y": 1, "Z": 1, "omega": 1, "phi": 1, "kappa": 1})), False,
       "sigma without orientation")
expect(broken(lambda d: d["images"][0].update(note="kept")), True, "unknown keys are allowed")
expect(broken(lambda d: d["cameras"][2]["fiducials"][0].pop("x_mm")), False, "fiducial without x_mm")
expect(broken(lambda d: d["images"][2]["inner_orientation"].update(photo_from_pixel=[[1, 2, 3]])), False,
       "inner orientation with one row")

print("%d passed, %d failed" % (passed, failed))
sys.exit(1 if failed else 0)
