"""Check rust-version declarations against the MSRV (used by .ci/msrv).

usage: msrv_check.py MSRV METADATA_JSON
"""

import json
import sys


def version(text):
    parts = [int(x) for x in text.split(".")]
    return tuple(parts + [0] * (3 - len(parts)))


def main():
    msrv_text, path = sys.argv[1], sys.argv[2]
    msrv = version(msrv_text)
    with open(path, encoding="utf-8") as f:
        meta = json.load(f)
    members = set(meta["workspace_members"])
    bad = []
    n_deps = 0
    for p in meta["packages"]:
        rv = p.get("rust_version")
        name = p["name"]
        if p["id"] in members:
            if rv is None or version(rv) != msrv:
                bad.append(f"workspace package {name} declares rust-version {rv}, not {msrv_text}")
        else:
            n_deps += 1
            if rv is not None and version(rv) > msrv:
                bad.append(f"dependency {name} {p['version']} needs Rust {rv} > {msrv_text}")
    if bad:
        print("\n".join(bad))
        sys.exit(1)
    print(
        f"ok: {len(members)} workspace packages declare {msrv_text}; "
        f"{n_deps} locked dependencies need at most {msrv_text} (or declare nothing)"
    )


if __name__ == "__main__":
    main()
