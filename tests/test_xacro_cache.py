"""The shipped models' xacro expansions come from the model cache: the same text as xacro's,
and a new expansion whenever a models/ file (an included one too) or an argument changes."""

import shutil

from omtp_drake import assets


def _entries(cache):
    return sorted(p.name for p in cache.rglob("xacro/*.urdf"))


def test_an_expansion_is_cached_and_redone_when_a_model_or_an_argument_changes(tmp_path, monkeypatch):
    models = tmp_path / "models"
    shutil.copytree(assets.MODELS_DIR, models)
    monkeypatch.setattr(assets, "MODELS_DIR", models)
    monkeypatch.setenv("OMTP_DRAKE_CACHE", str(tmp_path / "cache"))
    monkeypatch.delenv(assets.CACHE_LAYER_ENV, raising=False)
    bin_file = models / "bin.urdf.xacro"

    first = assets.expand_xacro(bin_file, {"name": "bin_1"})
    assert "bin_1" in first and len(_entries(tmp_path / "cache")) == 1
    (entry,) = (tmp_path / "cache").rglob("xacro/*.urdf")
    entry.write_text(first + "<!-- read from the cache -->")
    assert assets.expand_xacro(bin_file, {"name": "bin_1"}).endswith("<!-- read from the cache -->")

    second = assets.expand_xacro(bin_file, {"name": "bin_2"})  # another argument: expanded
    assert "bin_2" in second and "bin_1" not in second and len(_entries(tmp_path / "cache")) == 2

    # An included file changes (bin.urdf.xacro includes omtp_macros.xacro): expanded again.
    macros = models / "omtp_macros.xacro"
    macros.write_text(macros.read_text().replace('rgba="0.2 0.7 0.25 1"', 'rgba="0.2 0.7 0.125 1"'))
    third = assets.expand_xacro(bin_file, {"name": "bin_1"})
    assert 'rgba="0.2 0.7 0.125 1"' in third and len(_entries(tmp_path / "cache")) == 3
    assert third.replace("0.125", "0.25") == first  # the rest as before


def test_a_file_outside_models_is_never_cached(tmp_path, monkeypatch):
    monkeypatch.setenv("OMTP_DRAKE_CACHE", str(tmp_path / "cache"))
    own = tmp_path / "own.urdf.xacro"
    own.write_text('<robot name="mine" xmlns:xacro="http://www.ros.org/xacro"><link name="a"/></robot>')
    assert 'name="a"' in assets.expand_xacro(own)
    assert _entries(tmp_path / "cache") == []
