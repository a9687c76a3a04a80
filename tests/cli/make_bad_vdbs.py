"""Writes bad VDB inputs for `clothbake render`, each beside a scene that
uses it as an object's "volume" and the message expected (NAME.json,
NAME.expect), in the layout tests/cli/bad_inputs.sh checks.

    /usr/bin/python3 make_bad_vdbs.py GOOD.vdb SCENE_TEMPLATE.json OUT_DIR

GOOD.vdb is a volume written by `clothbake volume`; the template is a scene
whose objects[0] gets "volume" (mesh and cloth paths made absolute).
Needs pyopenvdb (Debian's python3-openvdb).
"""
import json
import os
import sys

import pyopenvdb as vdb

NEEDS = ("grid missing; a clothbake volume needs the grids density (float), tangent (vec3s), "
         "diffuse (vec3s), specular (float) and exponent (float)")


def grids_of(path):
    grids, meta = vdb.readAll(path)
    return {g.name: g for g in grids}, meta


def write_case(out_dir, template, name, grids, meta, message):
    vdb_path = os.path.join(out_dir, name + ".vdb")
    vdb.write(vdb_path, grids=list(grids), metadata=meta)
    scene = json.loads(json.dumps(template))
    scene["objects"][0]["volume"] = name + ".vdb"
    with open(os.path.join(out_dir, name + ".json"), "w") as f:
        json.dump(scene, f, indent=1)
    with open(os.path.join(out_dir, name + ".expect"), "w") as f:
        f.write(f"objects[0].volume: {vdb_path}: {message}")


def main():
    good, template_path, out_dir = sys.argv[1:4]
    os.makedirs(out_dir, exist_ok=True)
    template = json.load(open(template_path))
    base = os.path.dirname(os.path.abspath(template_path))
    for obj in template["objects"]:
        obj["mesh"] = os.path.join(base, obj["mesh"])
        if isinstance(obj.get("cloth"), str):
            obj["cloth"] = os.path.join(base, obj["cloth"])

    # A missing grid: no tangent.
    grids, meta = grids_of(good)
    write_case(out_dir, template, "vdb_missing_tangent",
               [g for n, g in grids.items() if n != "tangent"], meta, "tangent: " + NEEDS)

    # A grid of the wrong type: specular as a vector grid.
    grids, meta = grids_of(good)
    wrong = vdb.Vec3SGrid()
    wrong.name = "specular"
    wrong.transform = grids["specular"].transform
    wrong.getAccessor().setValueOn((0, 0, 0), (0.5, 0.5, 0.5))
    grids["specular"] = wrong
    write_case(out_dir, template, "vdb_wrong_type", grids.values(), meta,
               "specular: grid has values of type vec3s; expected float")

    # Density out of range at one voxel.
    grids, meta = grids_of(good)
    grids["density"].getAccessor().setValueOn((3, 4, 2), 1.25)
    write_case(out_dir, template, "vdb_density_out_of_range", grids.values(), meta,
               "density: voxel (3, 4, 2) is 1.25; density must be in [0, 1]")

    # Not a VDB at all.
    path = os.path.join(out_dir, "vdb_not_a_vdb.vdb")
    with open(path, "w") as f:
        f.write("not a volume\n")
    scene = json.loads(json.dumps(template))
    scene["objects"][0]["volume"] = "vdb_not_a_vdb.vdb"
    with open(os.path.join(out_dir, "vdb_not_a_vdb.json"), "w") as f:
        json.dump(scene, f, indent=1)
    with open(os.path.join(out_dir, "vdb_not_a_vdb.expect"), "w") as f:
        f.write(f"objects[0].volume: {path}: not a readable OpenVDB file")


if __name__ == "__main__":
    main()
