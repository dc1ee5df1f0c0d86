/* The one BVH traversal body: nearest child first with a stack of far children (Aila and
 * Laine, "Understanding the Efficiency of Ray Traversal on GPUs", 2009); leaf children are
 * intersected as soon as their box is hit. On a tree still being built (the on-demand paper,
 * section 3.3) a child whose link is unbuilt is requested from the pool when the ray gets
 * there, and the ray suspends, keeping its stack and its best hit; a restart re-reads the
 * parent's link. Instantiated by traversal/bvh_traverse.h ("template by include"):
 *
 *   #define LT_BVH_TRAVERSE_NAME      the function to define
 *   #define LT_BVH_TRAVERSE_ONDEMAND  1: links may be unbuilt and change under the ray
 *   #define LT_BVH_TRAVERSE_LEAF_TRIS 1: leaves are lt_tri in leaf order, 0: triangle numbers
 *
 * The function advances a ray started with lt_bvh_ray_start; it returns 1 when the ray is
 * done, 0 when it waits for an unbuilt node. flags are the query flags (LT_QUERY_FLAG_*: any
 * hit, the triangle test, the slab test). */

#define LT_BVH_CAT2(a, b) a##b
#define LT_BVH_CAT(a, b) LT_BVH_CAT2(a, b)
#define LT_BVH_LEAF LT_BVH_CAT(LT_BVH_TRAVERSE_NAME, _leaf)

/* Wide children (device/bvh_node.h) are taken as such by the on-demand traversal on the native
 * backend of x86 (the only place the host makes them); everywhere else they are inner nodes. */
#define LT_BVH_TRAVERSE_WIDE (LT_BVH_TRAVERSE_ONDEMAND && LT_BVH_WIDE)

/* Intersects the `count` references of a leaf from position `first`. */
LT_DEVICE_OUTLINE void LT_BVH_LEAF(const lt_bvh_view *v, const lt_ray_setup *r, lt_hit_record *hit, lt_i32 first, lt_i32 count,
                           lt_trace_counters *c) {
  for (lt_i32 i = first; i < first + count; i++) {
#if LT_BVH_TRAVERSE_LEAF_TRIS
    lt_tri tri = v->tris[i];
    float v0[3] = {tri.v0.x, tri.v0.y, tri.v0.z}, v1[3] = {tri.v1.x, tri.v1.y, tri.v1.z};
    float v2[3] = {tri.v2.x, tri.v2.y, tri.v2.z};
    lt_i32 prim = lt_float_as_int(tri.v0.w);
#else
    lt_i32 prim = v->index[i];
    LT_GLOBAL const float *t = v->verts + 9 * (long)prim;
    float v0[3] = {t[0], t[1], t[2]}, v1[3] = {t[3], t[4], t[5]}, v2[3] = {t[6], t[7], t[8]};
#endif
    c->intersections++;
    lt_intersect_triangle(r, v0, v1, v2, prim, hit);
  }
}

LT_DEVICE int LT_BVH_TRAVERSE_NAME(const lt_bvh_view *v, lt_bvh_ray *q, int flags, lt_trace_counters *c) {
  LT_GLOBAL const lt_bvh_node *nodes = v->nodes;
  int any_hit = flags & LT_QUERY_FLAG_ANY;
  q->r.flags = flags;

  /* The node, the stack pointer and the best hit live in locals while the ray moves, and go
   * back into the ray's state when it stops or suspends: compilers keep locals in registers,
   * and a hit apart from the ray cannot alias it. */
  const lt_ray_setup *r = &q->r;
  lt_hit_record hit = q->hit;
  lt_i32 cur = q->cur, sp = q->sp;
  int done = 1;
  for (;;) {
    if (any_hit && hit.prim >= 0) break;

#if LT_BVH_TRAVERSE_ONDEMAND
    /* A link reference: resolve it, or suspend on it. */
    if (cur <= -2) {
      lt_i32 address = -2 - cur, link, count;
      int kind = lt_bvh_read_link(nodes, address, &link, &count);
      if (kind == LT_CHILD_UNBUILT) {
        if (q->wait != address) {
          lt_pool_request(v->pool, lt_bvh_unbuilt_slot(link), address);
          lt_pool_count(v->pool, LT_POOL_STAT_STALLS, 1);
          q->wait = address;
        }
        done = 0;
        break;
      }
      q->wait = -1;
      if (kind == LT_CHILD_LEAF) LT_BVH_LEAF(v, r, &hit, link, count, c);
#if LT_BVH_TRAVERSE_WIDE
      /* A wide child: its subtree through the 8-wide traversal, from the best hit so far, its
       * exits onto the stack; then on from the stack like after a leaf. Exits that would not
       * fit send the ray into the binary subtree instead (its links are all still there). */
      if (kind == LT_CHILD_INNER && lt_bvh_child_is_wide(count) &&
          lt__bvh_wide_trace(v->wide, r, &hit, lt_bvh_wide_node(count), q->stack, q->stack_t, &sp,
                             LT_BVH_RAY_STACK_SIZE, c) == 0)
        kind = LT_CHILD_LEAF;
#endif
      if (kind == LT_CHILD_INNER) {
        cur = link;
      } else {
        q->sp = sp, q->hit = hit;
        cur = lt_bvh_ray_pop(q);
        sp = q->sp;
      }
      continue;
    }
#endif
    if (cur < 0) break;

    /* The node's boxes; in a growing tree its links are read one by one, atomically, in a
     * finished one with plain loads. */
    c->traversal_steps++;
    LT_GLOBAL const lt_bvh_node *n = &nodes[cur];
    lt_float4 lxy = n->left_xy, rxy = n->right_xy, z = n->lr_z;
    float lo[2][3] = {{lxy.x, lxy.z, z.x}, {rxy.x, rxy.z, z.z}};
    float hi[2][3] = {{lxy.y, lxy.w, z.y}, {rxy.y, rxy.w, z.w}};

    /* Both children's boxes against the ray, up to the best hit so far, before any leaf is
     * intersected (a call between the two box tests would spill what they share). */
    float best = hit.prim >= 0 ? hit.t : r->tmax;
    lt_i32 link[2], count[2], next[2];
    float t_entry[2];
    int go[2], kind[2];
    /* Unrolled on growing trees too: as a loop over arrays in memory the on-demand traversal
     * ran 1.25x the finished one's instructions a ray (docs/notes/trace_speed.md). */
    LT_UNROLL_2
    for (int side = 0; side < 2; side++) {
#if LT_BVH_TRAVERSE_ONDEMAND
      kind[side] = lt_bvh_read_child_acquire(n, side, &link[side], &count[side]);
#else
      kind[side] = lt_bvh_child(n, side, &link[side], &count[side]);
#endif
      go[side] = kind[side] != LT_CHILD_EMPTY && lt_ray_box(r, lo[side], hi[side], best, &t_entry[side]);
    }

    /* Leaves now; inner nodes go on; an unbuilt child is requested when the ray gets there
     * (the far one may be hidden by then). */
    for (int side = 0; side < 2; side++) {
      if (!go[side]) continue;
      if (kind[side] == LT_CHILD_LEAF) {
        LT_BVH_LEAF(v, r, &hit, link[side], count[side], c);
        go[side] = 0;
      } else if (kind[side] == LT_CHILD_UNBUILT) {
        next[side] = -2 - (cur * 2 + side);
#if LT_BVH_TRAVERSE_WIDE
      } else if (lt_bvh_child_is_wide(count[side])) {
        /* A wide child is taken in its turn, nearer first, through its link (above). */
        next[side] = -2 - (cur * 2 + side);
#endif
      } else {
        next[side] = link[side];
      }
    }
    if (any_hit && hit.prim >= 0) break;

    /* The nearer child next, the farther one on the stack. */
    if (go[0] && go[1]) {
      int near_side = t_entry[0] <= t_entry[1] ? 0 : 1;
      if (sp == LT_BVH_RAY_STACK_SIZE) {
#if LT_BVH_TRAVERSE_ONDEMAND
        lt_pool_fail(v->pool, LT_POOL_ERROR_STACK);
#endif
        q->overflow = 1;
        break;
      }
      q->stack[sp] = next[1 - near_side];
#if LT_BVH_TRAVERSE_CULL_POPS
      q->stack_t[sp] = t_entry[1 - near_side];
#endif
      sp++;
      cur = next[near_side];
    } else if (go[0] || go[1]) {
      cur = go[0] ? next[0] : next[1];
    } else {
#if LT_BVH_TRAVERSE_CULL_POPS
      /* The next far child the best hit so far has not ruled out (lt_bvh_ray_pop). */
      float best_now = hit.prim >= 0 ? hit.t : r->tmax;
      cur = -1;
      while (sp > 0) {
        sp--;
        if (q->stack_t[sp] <= best_now) {
          cur = q->stack[sp];
          break;
        }
      }
#else
      cur = sp > 0 ? q->stack[--sp] : -1;
#endif
    }
  }
  q->cur = cur, q->sp = sp, q->hit = hit;
  return done;
}

#undef LT_BVH_LEAF
#undef LT_BVH_TRAVERSE_WIDE
#undef LT_BVH_CAT
#undef LT_BVH_CAT2
#undef LT_BVH_TRAVERSE_NAME
#undef LT_BVH_TRAVERSE_ONDEMAND
#undef LT_BVH_TRAVERSE_LEAF_TRIS
#undef LT_BVH_TRAVERSE_CULL_POPS
