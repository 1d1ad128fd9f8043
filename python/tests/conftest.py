"""Shared data for the tests: `$MX_SHARED` (the folder holding `data/`), else
`../shared` from the repository root. Missing data skips on a developer
machine and fails in CI (`CI=true`), never passing silently."""

import json
import os
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def shared_data() -> Path:
    root = Path(os.environ.get("MX_SHARED", REPO.parent / "shared"))
    data = root / "data"
    if not data.is_dir():
        msg = f"shared data folder {data} is missing (set MX_SHARED)"
        if os.environ.get("CI") == "true":
            pytest.fail(msg)
        pytest.skip(msg)
    return data


def shared_files(sub: str, suffix: str):
    folder = shared_data() / sub
    files = sorted(p for p in folder.iterdir() if p.name.endswith(suffix))
    if not files:
        pytest.fail(f"{folder} has no *{suffix} files")
    return files


@pytest.fixture(scope="session")
def references():
    """Every Pinocchio reference: (urdf path, parsed json)."""
    out = []
    for j in shared_files("reference", ".json"):
        ref = json.loads(j.read_text())
        out.append((j.parent / ref["urdf_file"], ref))
    return out


@pytest.fixture(scope="session")
def bvh_files():
    return shared_files("mocap", ".bvh")


@pytest.fixture(scope="session")
def walk_path():
    p = shared_data() / "mocap" / "bandai1_walk_normal_001.bvh"
    if not p.exists():
        pytest.fail(f"{p} is missing")
    return p
