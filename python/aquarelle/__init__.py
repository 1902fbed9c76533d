"""Aquarelle from Python: scenes, G-buffers, styles and every target as NumPy arrays.

    import aquarelle as aq
    scene = aq.load_scene("scenes/data/oak.json")
    gb = aq.rasterize(scene, 1280, 720, threads=2)
    out = aq.style("wc18").with_params({"edge_darken.intensity": 2.0}).run(gb)
    img = out["final"]          # float32 H x W x 3, a read-only view (no copy)

The module is the library `aquarelle render` runs (docs/python.md): the same images, the same
errors (aquarelle.Error, with the library's messages), the same files from aquarelle.render.
"""
from ._aquarelle import (  # noqa: F401
    Error,
    GBuffer,
    Result,
    Scene,
    Style,
    coherence,
    coherence_report,
    compare,
    load_scene,
    rasterize,
    register_stage,
    render,
    save,
    stages,
    style,
    styles,
)

__all__ = ["Error", "GBuffer", "Result", "Scene", "Style", "coherence", "coherence_report", "compare", "load_scene", "rasterize", "register_stage", "render", "save",
           "stages", "style", "styles"]
