"""The include graph of lib/src by folder: no folder includes one above it (so no circle).

An include of a lib/src file counts as its folder; an include of a public header
snvr/X.hpp counts as the folder that implements X (HEADER_FOLDER). Run with the
repository's root as the argument (CTest does); exits 1 naming every include that
climbs.
"""
import pathlib
import re
import sys

# Lowest first; a folder may include its own files and those of lower ranks only.
RANKS = {
    "": 0,          # lib/src/*.hpp, and public headers of types alone (implemented nowhere or in lib/src)
    "grid": 1,
    "geometry": 2,  # points, their tree, fields, the sampler's shapes
    "io": 3, "mesh": 3,  # files; meshes (neither includes the other)
    "solver": 3.5,  # the method, whose tiles make their part of the surface (mesh below it)
    "check": 4, "render": 4, "openmp": 4, "opencl": 4,
    "devices": 5,
    "pipeline": 6,  # the job's policy, above everything it composes
}
HEADER_FOLDER = {
    "error": "", "domain": "", "stopwatch": "",
    "geometry": "geometry", "point_cloud": "geometry", "field": "geometry", "shapes": "geometry",
    "point_io": "io", "mesh_io": "io", "formats": "io",
    "mesh": "mesh",
    "parameters": "solver", "reconstruct": "solver", "tiles": "solver",
    "quality": "check", "render": "render", "devices": "devices",
    "shell": "pipeline", "report": "pipeline",
    "snvr": "pipeline",  # the umbrella includes everything
}


def folder_of(path, src):
    rel = path.relative_to(src)
    return rel.parts[0] if len(rel.parts) > 1 else ""


def main(root):
    src = root / "lib" / "src"
    public = {p.stem for p in (root / "lib" / "include" / "snvr").glob("*.hpp")}
    problems = []
    unmapped = public - HEADER_FOLDER.keys()
    if unmapped:
        problems.append("public headers without a folder in HEADER_FOLDER: " + ", ".join(sorted(unmapped)))
    for f in sorted(src.rglob("*")):
        if f.suffix not in (".cpp", ".hpp"):
            continue
        here = folder_of(f, src)
        if here not in RANKS:
            problems.append(f"{f.relative_to(root)}: folder '{here}' has no rank")
            continue
        for n, line in enumerate(f.read_text().splitlines(), 1):
            m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
            if not m:
                continue
            target = m.group(1)
            pub = re.fullmatch(r"snvr/(\w+)\.hpp", target)
            if pub:
                there = HEADER_FOLDER.get(pub.group(1))
                if there is None:
                    continue  # reported above
            elif (src / target).exists():
                there = folder_of(src / target, src)
            else:
                continue  # generated or outside the library (the kernels' header)
            if there != here and RANKS.get(there, 99) >= RANKS[here]:
                problems.append(f"{f.relative_to(root)}:{n}: {here or 'lib/src'} includes {target} ({there or 'lib/src'}), "
                                f"not below it")
    for p in problems:
        print(p)
    print(f"include layers: {len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()))
