"""Loading liblazytrace.so and declaring the C functions the module calls (ctypes).

The library is looked for, in this order:
  1. the path in the environment variable LAZYTRACE_LIBRARY;
  2. beside an installed module: the path written into _installed.py at install time;
  3. in a source checkout: build/liblazytrace.so next to the python/ folder;
  4. wherever the dynamic loader finds liblazytrace.so.0 (ld.so.conf, LD_LIBRARY_PATH).
"""
import ctypes
import ctypes.util
import os

c_int, c_float, c_double, c_size_t = ctypes.c_int, ctypes.c_float, ctypes.c_double, ctypes.c_size_t
c_char_p, c_void_p = ctypes.c_char_p, ctypes.c_void_p

SONAME = "liblazytrace.so.0"


class ContextConfig(ctypes.Structure):
    """lt_context_config."""
    _fields_ = [("device", c_int), ("opencl_index", c_int), ("work_groups", c_int),
                ("local_size", c_int), ("quiet", c_int)]


class StructureConfig(ctypes.Structure):
    """lt_structure_config; the module fills it through lt_structure_option, by name."""
    _fields_ = [("kind", c_int), ("build", c_int), ("max_leaf_size", c_int), ("sah_bins", c_int),
                ("traversal_cost", c_float), ("pool_capacity", c_int), ("intersect", c_int),
                ("grid_density", c_float), ("kd_traversal", c_int), ("kd_split", c_int),
                ("kd_clip", c_int), ("irgrid_top_density", c_float),
                ("irgrid_cell_density", c_float), ("irgrid_merge", c_int),
                ("irgrid_merge_alpha", c_float), ("irgrid_expansion_passes", c_int),
                ("bvh_builder", c_int), ("bvh_top", c_int), ("bvh_morton_above", c_int)]


def _candidates():
    """The places to try, each with the reason it is tried (for the error message)."""
    here = os.path.dirname(os.path.abspath(__file__))
    env = os.environ.get("LAZYTRACE_LIBRARY")
    if env:
        yield env, "LAZYTRACE_LIBRARY"
        return
    try:
        from . import _installed
        yield os.path.normpath(os.path.join(here, _installed.LIBRARY)), "the install prefix"
    except ImportError:
        pass
    yield os.path.normpath(os.path.join(here, "..", "..", "build", "liblazytrace.so")), "the build tree"
    yield ctypes.util.find_library("lazytrace") or SONAME, "the dynamic loader"


def load():
    tried = []
    for path, why in _candidates():
        if os.sep in path and not os.path.exists(path):
            tried.append(f"{path} ({why}): no such file")
            continue
        try:
            return _declare(ctypes.CDLL(path))
        except OSError as error:
            tried.append(f"{path} ({why}): {error}")
    raise ImportError("lazytrace: cannot load the shared library; set LAZYTRACE_LIBRARY to its path. Tried:\n  "
                      + "\n  ".join(tried))


def _declare(lib):
    """Argument and result types of every function the module calls."""
    P = c_void_p
    signatures = {
        "lt_version": (c_char_p, []),
        "lt_status_name": (c_char_p, [c_int]),
        "lt_status_str": (c_char_p, [c_int]),
        "lt_last_error": (c_char_p, []),
        "lt_context_create": (c_int, [ctypes.POINTER(ContextConfig), ctypes.POINTER(P)]),
        "lt_context_destroy": (None, [P]),
        "lt_context_device_name": (c_char_p, [P]),
        "lt_context_compile_ms": (c_double, [P]),
        "lt_scene_load": (c_int, [c_char_p, ctypes.POINTER(P)]),
        "lt_scene_from_triangles": (c_int, [P, c_size_t, ctypes.POINTER(P)]),
        "lt_scene_destroy": (None, [P]),
        "lt_scene_triangle_count": (c_size_t, [P]),
        "lt_scene_triangles": (ctypes.POINTER(c_float), [P]),
        "lt_scene_skipped_triangles": (c_size_t, [P]),
        "lt_scene_bounds": (None, [P, P, P]),
        "lt_structure_kind_parse": (c_int, [c_char_p, ctypes.POINTER(c_int)]),
        "lt_structure_kind_name": (c_char_p, [c_int]),
        "lt_build_mode_parse": (c_int, [c_char_p, ctypes.POINTER(c_int)]),
        "lt_build_mode_name": (c_char_p, [c_int]),
        "lt_intersect_kind_parse": (c_int, [c_char_p, ctypes.POINTER(c_int)]),
        "lt_structure_config_default": (StructureConfig, [c_int]),
        "lt_structure_option": (c_int, [ctypes.POINTER(StructureConfig), c_char_p, c_char_p]),
        "lt_structure_variants": (c_size_t, [P, P, c_size_t]),
        "lt_structure_create": (c_int, [P, P, ctypes.POINTER(StructureConfig), P, ctypes.POINTER(P)]),
        "lt_structure_destroy": (None, [P]),
        "lt_structure_trace": (c_int, [P, P, c_size_t, c_int, P, P]),
        "lt_reference_trace": (c_int, [P, P, c_size_t, c_int, P]),
        "lt_stats_create": (c_int, [ctypes.POINTER(P)]),
        "lt_stats_destroy": (None, [P]),
        "lt_stats_get": (c_double, [P, c_char_p]),
        "lt_stats_key": (c_char_p, [c_size_t]),
        "lt_stats_text": (c_char_p, [P, c_char_p]),
    }
    for name, (restype, argtypes) in signatures.items():
        function = getattr(lib, name)
        function.restype, function.argtypes = restype, argtypes
    return lib
