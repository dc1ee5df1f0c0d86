"""lazytrace for Python: batches of ray queries over numpy arrays.

    import numpy as np, lazytrace
    scene = lazytrace.Scene.from_arrays(vertices, faces)       # or Scene.load("sphere:3")
    bvh = lazytrace.Structure(scene, kind="bvh", build="speculative")
    t, prim, u, v = bvh.intersect(origins, directions)          # closest hits; prim -1 on a miss
    blocked = bvh.occluded(origins, directions, tmax=1.0)       # any hit in [tmin, tmax]

A structure persists across calls: an on-demand build goes on where the last batch left it, so
repeated queries build only what they newly reach. Arrays may be float32 or float64, of any
length, C-contiguous or not; the library computes in float32, as the C API does, and returns
exactly the C API's hits for the same (float32) rays. The trimesh-shaped helpers
(intersects_first, intersects_any, intersects_location, intersects_id) take a trimesh user's
arguments, and RayMeshIntersector(mesh) stands in for trimesh's own intersector.

A call that fails raises LazytraceError, whose message is the library's (lt_last_error()); bad
arrays raise ValueError or TypeError before anything reaches the library.
"""
import collections
import ctypes
import threading
import weakref

import numpy as np

from . import _native

_lib = _native.load()

__all__ = ["LazytraceError", "Context", "Scene", "Structure", "Hits", "RayMeshIntersector", "variants",
           "version", "RAY_DTYPE", "HIT_DTYPE"]

# The C records: lt_ray (32 bytes) and lt_hit (16 bytes), as in the ray and hit files.
RAY_DTYPE = np.dtype([("org", "<f4", 3), ("tmin", "<f4"), ("dir", "<f4", 3), ("tmax", "<f4")])
HIT_DTYPE = np.dtype([("t", "<f4"), ("u", "<f4"), ("v", "<f4"), ("prim", "<i4")])
# lt_structure_trace takes at most 2^28 rays at once; longer arrays go in batches of this size.
_BATCH = 1 << 26
_QUERY_CLOSEST, _QUERY_ANY = 0, 1
_DEVICES = {"auto": 0, "opencl": 1, "native": 2}

Hits = collections.namedtuple("Hits", "t prim u v")
Hits.__doc__ = """Closest hits: t (float32, inf on a miss), prim (int64 triangle, -1 on a miss), u, v
(float32 barycentrics: the hit point is (1-u-v)*v0 + u*v1 + v*v2)."""


class LazytraceError(RuntimeError):
    """A failing library call: status (the lt_status number), name ("LT_ERROR_PARSE") and the
    library's message (lt_last_error())."""

    def __init__(self, status, message):
        self.status = status
        self.name = _lib.lt_status_name(status).decode()
        self.message = message or _lib.lt_status_str(status).decode()
        super().__init__(f"{self.name}: {self.message}")


def _check(status):
    if status != 0:
        raise LazytraceError(status, _lib.lt_last_error().decode(errors="replace"))


def version():
    """The shared library's version, "MAJOR.MINOR.PATCH"."""
    return _lib.lt_version().decode()


def variants():
    """Every (structure, build mode) pair the library implements, as names, in registry order."""
    kinds, modes = (ctypes.c_int * 256)(), (ctypes.c_int * 256)()
    n = _lib.lt_structure_variants(kinds, modes, 256)
    return [(_lib.lt_structure_kind_name(kinds[i]).decode(), _lib.lt_build_mode_name(modes[i]).decode())
            for i in range(n)]


class Context:
    """A compute device: device="auto" (OpenCL if a device exists, else native), "native",
    "opencl" or "opencl:N". work_groups and local_size shape the launches (0: the device's own);
    quiet=True silences the library's notes on stderr (such as falling back to native)."""

    def __init__(self, device="auto", work_groups=0, local_size=0, quiet=False):
        kind, _, index = str(device).partition(":")
        if kind not in _DEVICES or (index and (kind != "opencl" or not index.isdigit())):
            raise ValueError(f"device {device!r}: expected auto, native, opencl or opencl:N")
        config = _native.ContextConfig(_DEVICES[kind], int(index or 0), int(work_groups), int(local_size),
                                       1 if quiet else 0)
        handle = ctypes.c_void_p()
        _check(_lib.lt_context_create(ctypes.byref(config), ctypes.byref(handle)))
        self._handle = handle
        self._finalizer = weakref.finalize(self, _lib.lt_context_destroy, handle)

    @property
    def device_name(self):
        """"native (2 threads)", "opencl:0 (cpu-...)", ..."""
        return _lib.lt_context_device_name(self._handle).decode()

    @property
    def compile_ms(self):
        """Milliseconds spent compiling kernels in this context so far."""
        return _lib.lt_context_compile_ms(self._handle)

    def __repr__(self):
        return f"<lazytrace.Context {self.device_name}>"


_default_context = None
_default_lock = threading.Lock()


def _context_or_default(context):
    global _default_context
    if context is not None:
        return context
    with _default_lock:
        if _default_context is None:
            _default_context = Context()
        return _default_context


class Scene:
    """Triangles, numbered in the order they are given (Scene.from_arrays) or read (Scene.load)."""

    def __init__(self, handle, face_index=None):
        self._handle = handle
        # Where faces with NaN or infinite coordinates were left out, the library's triangle
        # numbers skip them: face_index maps its numbers back to the caller's faces.
        self._face_index = face_index
        self._finalizer = weakref.finalize(self, _lib.lt_scene_destroy, handle)

    @classmethod
    def load(cls, spec):
        """A generator ("sphere:3", "house-grid:3x3@close"), a mesh file (.obj, .ply, .gltf, ...)
        or a scene file (.json), as the command line takes them."""
        handle = ctypes.c_void_p()
        _check(_lib.lt_scene_load(str(spec).encode(), ctypes.byref(handle)))
        return cls(handle)

    @classmethod
    def from_arrays(cls, vertices, faces):
        """vertices: (V, 3) numbers; faces: (F, 3) integer indices into vertices. Triangle i is
        faces[i]. Faces with a NaN or infinite coordinate are never hit."""
        vertices = _array(vertices, "vertices", (None, 3), np.float64)
        faces = np.asarray(faces)
        if faces.ndim != 2 or faces.shape[1] != 3:
            raise ValueError(f"faces: expected shape (F, 3), got {faces.shape}")
        if faces.size and not np.issubdtype(faces.dtype, np.integer):
            raise TypeError(f"faces: expected integer indices, got {faces.dtype}")
        faces = faces.astype(np.int64, copy=False)
        if faces.size and (faces.min() < 0 or faces.max() >= len(vertices)):
            raise ValueError(f"faces: indices must lie in [0, {len(vertices)}), found {faces.min()} to {faces.max()}")
        with np.errstate(over="ignore"):  # coordinates beyond float32 become inf: such faces are left out
            triangles = np.ascontiguousarray(vertices.astype(np.float32)[faces].reshape(-1, 9))
        finite = np.isfinite(triangles).all(axis=1)
        face_index = None if finite.all() else np.flatnonzero(finite)
        handle = ctypes.c_void_p()
        _check(_lib.lt_scene_from_triangles(triangles.ctypes.data, len(triangles), ctypes.byref(handle)))
        return cls(handle, face_index)

    @property
    def triangle_count(self):
        """Triangles the library holds (faces with non-finite coordinates are not among them)."""
        return _lib.lt_scene_triangle_count(self._handle)

    @property
    def triangles(self):
        """(triangle_count, 3, 3) float32: the vertices of every triangle the library holds."""
        n = self.triangle_count
        if n == 0:
            return np.empty((0, 3, 3), np.float32)
        pointer = _lib.lt_scene_triangles(self._handle)
        return np.ctypeslib.as_array(pointer, shape=(n * 9,)).reshape(n, 3, 3).copy()

    @property
    def bounds(self):
        """(lo, hi): the corners of the box around every triangle."""
        lo, hi = np.zeros(3, np.float32), np.zeros(3, np.float32)
        _lib.lt_scene_bounds(self._handle, lo.ctypes.data, hi.ctypes.data)
        return lo, hi

    def _faces(self, prim):
        """The caller's face numbers for the library's triangle numbers (-1 stays -1)."""
        prim = prim.astype(np.int64)
        if self._face_index is not None:
            hit = prim >= 0
            prim[hit] = self._face_index[prim[hit]]
        return prim

    def __repr__(self):
        return f"<lazytrace.Scene {self.triangle_count} triangles>"


def _array(a, name, shape, dtype):
    """a as an ndarray of a numeric dtype and the given shape (None: any length)."""
    try:
        a = np.asarray(a)
    except Exception as error:  # ragged lists and the like
        raise ValueError(f"{name}: not an array ({error})") from None
    if a.dtype.kind not in "fiub":
        raise TypeError(f"{name}: expected numbers, got dtype {a.dtype}")
    if a.ndim != len(shape) or any(want is not None and got != want for got, want in zip(a.shape, shape)):
        expected = "(" + ", ".join("N" if s is None else str(s) for s in shape) + ")"
        raise ValueError(f"{name}: expected shape {expected}, got {a.shape}")
    return a.astype(dtype, copy=False)


def _pack_rays(origins, directions, tmin, tmax):
    """The lt_ray records for the rays: origins and directions (N, 3) (one of them may be a
    single (3,) row shared by every ray), tmin and tmax scalars or (N,) arrays."""
    o, d = np.asarray(origins), np.asarray(directions)
    if o.ndim == 1:
        o = _array(o, "origins", (3,), np.float32)[None, :]
    if d.ndim == 1:
        d = _array(d, "directions", (3,), np.float32)[None, :]
    o = _array(o, "origins", (None, 3), np.float32)
    d = _array(d, "directions", (None, 3), np.float32)
    n = max(len(o), len(d))
    if len(o) not in (1, n) or len(d) not in (1, n):
        raise ValueError(f"origins and directions: {len(o)} and {len(d)} rays do not match")
    rays = np.empty(n, RAY_DTYPE)
    rays["org"], rays["dir"] = o, d
    for key, value in (("tmin", tmin), ("tmax", tmax)):
        value = np.asarray(value)
        if value.ndim > 1 or (value.ndim == 1 and len(value) != n):
            raise ValueError(f"{key}: expected a number or {n} of them, got shape {value.shape}")
        rays[key] = _array(value, key, value.shape, np.float32)
    return rays


class Structure:
    """An acceleration structure over a scene, on a context's device.

    kind: "bvh" (default), "lbvh", "grid", "kdtree", "irgrid"; build: "full", "requested",
    "speculative" or None (the structure's default). Further keyword arguments are the
    structure's options as the command line names them, with dashes as underscores:
    leaf_size=8, bins=16, grid_density=2, traversal="restart", intersect="fast", ...
    ('lazytrace help' lists them). stats=True gathers statistics on every call (on-demand
    builds then trace each batch a second time, to tell build time from trace time)."""

    def __init__(self, scene, kind="bvh", build=None, context=None, stats=False, **options):
        if not isinstance(scene, Scene):
            raise TypeError("scene: expected a lazytrace.Scene")
        self.scene, self.context = scene, _context_or_default(context)
        config = self._config(kind, build, options)
        self._stats = ctypes.c_void_p()
        _check(_lib.lt_stats_create(ctypes.byref(self._stats)))
        self._stats_finalizer = weakref.finalize(self, _lib.lt_stats_destroy, self._stats)
        self._collect = bool(stats)
        handle = ctypes.c_void_p()
        _check(_lib.lt_structure_create(self.context._handle, scene._handle, ctypes.byref(config), self._stats,
                                        ctypes.byref(handle)))
        self._handle = handle
        self._finalizer = weakref.finalize(self, _lib.lt_structure_destroy, handle)
        # One batch at a time: the library releases the GIL while it traces.
        self._lock = threading.Lock()

    @staticmethod
    def _config(kind, build, options):
        value = ctypes.c_int()
        _check(_lib.lt_structure_kind_parse(str(kind).encode(), ctypes.byref(value)))
        config = _lib.lt_structure_config_default(value.value)
        if build is not None:
            _check(_lib.lt_build_mode_parse(str(build).encode(), ctypes.byref(value)))
            config.build = value.value
        for name, setting in options.items():
            if name == "intersect":
                _check(_lib.lt_intersect_kind_parse(str(setting).encode(), ctypes.byref(value)))
                config.intersect = value.value
                continue
            option = "--" + name.replace("_", "-")
            _check(_lib.lt_structure_option(ctypes.byref(config), option.encode(), str(setting).encode()))
        return config

    def _trace(self, rays, query):
        hits = np.empty(len(rays), HIT_DTYPE)
        stats = self._stats if self._collect else None
        with self._lock:
            for start in range(0, len(rays), _BATCH):
                part = rays[start:start + _BATCH]
                _check(_lib.lt_structure_trace(self._handle, part.ctypes.data, len(part), query,
                                               hits[start:].ctypes.data, stats))
        return hits

    def trace_records(self, rays, any_hit=False):
        """The C API's own records: rays a RAY_DTYPE array (or (N, 8) float32: ox oy oz tmin dx
        dy dz tmax, as in a ray file); returns a HIT_DTYPE array of the library's triangle
        numbers, as in a hit file."""
        rays = np.asarray(rays)
        if rays.dtype != RAY_DTYPE:
            rays = _array(rays, "rays", (None, 8), np.float32)
        rays = np.ascontiguousarray(rays).view(RAY_DTYPE).reshape(-1)
        return self._trace(rays, _QUERY_ANY if any_hit else _QUERY_CLOSEST)

    def intersect(self, origins, directions, tmin=0.0, tmax=np.inf):
        """Closest hits of the rays origin + t * direction, tmin <= t <= tmax (t in direction
        lengths): Hits(t, prim, u, v), one entry per ray, prim -1 and t inf on a miss. Rays with
        a NaN or infinite component, a zero direction or tmin > tmax miss."""
        hits = self._trace(_pack_rays(origins, directions, tmin, tmax), _QUERY_CLOSEST)
        return Hits(hits["t"].copy(), self.scene._faces(hits["prim"]), hits["u"].copy(), hits["v"].copy())

    def occluded(self, origins, directions, tmin=0.0, tmax=np.inf):
        """Whether anything lies on each ray between tmin and tmax: a bool array."""
        return self._trace(_pack_rays(origins, directions, tmin, tmax), _QUERY_ANY)["prim"] >= 0

    # ---- trimesh-shaped helpers: the names and results of trimesh's ray intersectors ----

    def intersects_first(self, ray_origins, ray_directions):
        """The first triangle each ray hits (int64), -1 where it hits none."""
        return self.intersect(ray_origins, ray_directions).prim

    def intersects_any(self, ray_origins, ray_directions):
        """Whether each ray hits any triangle (bool)."""
        return self.occluded(ray_origins, ray_directions)

    def intersects_id(self, ray_origins, ray_directions, multiple_hits=True, max_hits=20,
                      return_locations=False):
        """(index_tri, index_ray[, locations]) of the hits: the first of each ray, or with
        multiple_hits every surface each ray crosses (up to max_hits), in order along the ray.
        A ray crossing an edge or a vertex shared by several triangles counts one of them, as
        does a ray through coincident triangles."""
        rays = _pack_rays(ray_origins, ray_directions, 0.0, np.inf)
        index_ray, index_tri, t, u, v = [], [], [], [], []
        active = np.arange(len(rays))
        for _ in range(max_hits if multiple_hits else 1):
            if len(active) == 0:
                break
            hits = self._trace(rays[active], _QUERY_CLOSEST)
            hit = hits["prim"] >= 0
            active, hits = active[hit], hits[hit]
            index_ray.append(active), index_tri.append(hits["prim"]), t.append(hits["t"])
            u.append(hits["u"]), v.append(hits["v"])
            # The next surface lies strictly beyond this one: a triangle's distance along a
            # ray is computed the same way every time, so the one just hit cannot come back.
            rays["tmin"][active] = np.nextafter(hits["t"], np.float32(np.inf))
        index_ray = np.concatenate(index_ray) if index_ray else np.empty(0, np.int64)
        prim = np.concatenate(index_tri) if index_tri else np.empty(0, np.int32)
        order = np.argsort(index_ray, kind="stable")
        index_ray, prim = index_ray[order].astype(np.int64), prim[order]
        result = (self.scene._faces(prim), index_ray)
        if return_locations:
            u = np.concatenate(u)[order] if u else np.empty(0, np.float32)
            v = np.concatenate(v)[order] if v else np.empty(0, np.float32)
            result += (self._locations(prim, u, v),)
        return result

    def intersects_location(self, ray_origins, ray_directions, multiple_hits=True):
        """(locations (K, 3), index_ray (K,), index_tri (K,)) of the hits, as intersects_id."""
        index_tri, index_ray, locations = self.intersects_id(ray_origins, ray_directions, multiple_hits,
                                                             return_locations=True)
        return locations, index_ray, index_tri

    def _locations(self, prim, u, v):
        """Hit points from barycentrics on the library's triangles, in float64."""
        if not hasattr(self, "_triangles"):
            self._triangles = self.scene.triangles.astype(np.float64)
        tri = self._triangles[prim]
        u, v = u.astype(np.float64)[:, None], v.astype(np.float64)[:, None]
        return (1 - u - v) * tri[:, 0] + u * tri[:, 1] + v * tri[:, 2]

    @property
    def stats(self):
        """The statistics so far, as the command line's --stats JSON object: the structure's
        build and, with stats=True, the traces' counters summed over every call. A key that
        does not apply is None; dotted keys ("pool.tasks") are nested dicts."""
        result = {key: _lib.lt_stats_text(self._stats, key.encode()).decode() or None
                  for key in ("structure", "build", "device", "intersect")}
        i = 0
        while (key := _lib.lt_stats_key(i)) is not None:
            value = _lib.lt_stats_get(self._stats, key)
            value = None if value < 0 else int(value) if value.is_integer() and b"ms" not in key else value
            group, _, member = key.decode().rpartition(".")
            (result.setdefault(group, {}) if group else result)[member] = value
            i += 1
        for key, group in result.items():  # a group of which nothing applies is None, as in JSON
            if isinstance(group, dict) and all(v is None for v in group.values()) and key != "pool":
                result[key] = None
        return result

    def __repr__(self):
        return f"<lazytrace.Structure {self.stats['structure']} {self.stats['build']} on {self.context.device_name}>"


class RayMeshIntersector(Structure):
    """A drop-in for trimesh's ray intersectors: RayMeshIntersector(mesh) over any object with
    vertices (V, 3) and faces (F, 3), with intersects_first, intersects_any,
    intersects_location and intersects_id. Keyword arguments go to Structure."""

    def __init__(self, mesh, **kwargs):
        self.mesh = mesh
        super().__init__(Scene.from_arrays(mesh.vertices, mesh.faces), **kwargs)
