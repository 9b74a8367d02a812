"""expand_xacro keeps the expansions of models/ for the process, and expands again once the
file or a file it includes changed (a developer editing models/ in a running notebook)."""

import shutil

from omtp_drake import assets


def test_an_expansion_is_kept_until_the_file_or_its_include_changes(tmp_path, monkeypatch):
    for name in ("bin.urdf.xacro", "omtp_macros.xacro"):
        shutil.copy(assets.MODELS_DIR / name, tmp_path / name)
    monkeypatch.setattr(assets, "MODELS_DIR", tmp_path)
    monkeypatch.setattr(assets, "_EXPANDED", {})
    first = assets.expand_xacro(tmp_path / "bin.urdf.xacro", {"name": "bin_9"})
    assert "bin_9" in first and len(assets._EXPANDED) == 1
    assert len(assets._EXPANDED[next(iter(assets._EXPANDED))][0]) == 2  # the file and its include
    assert assets.expand_xacro(tmp_path / "bin.urdf.xacro", {"name": "bin_9"}) is first
    assert "bin_8" in assets.expand_xacro(tmp_path / "bin.urdf.xacro", {"name": "bin_8"})  # other args
    macros = tmp_path / "omtp_macros.xacro"
    macros.write_text(macros.read_text().replace("<robot", "<!-- edited -->\n<robot", 1) + "\n")
    again = assets.expand_xacro(tmp_path / "bin.urdf.xacro", {"name": "bin_9"})
    assert again is not first and again == first  # expanded again (same URDF: only a comment)
