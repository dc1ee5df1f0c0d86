/* The QBVH traversal (Bogolepov and Ulyanov, "One approach to traversing QBVH on a GPU"): at
 * each node the ray meets the four children's boxes at once, sorts the ones it enters near to
 * far with the paper's network of five compare-exchanges, intersects the leaves among them at
 * once in that order (as the binary BVH's traversal does, so that a near leaf's hit culls the
 * rest), goes on to the nearest inner child and pushes the other inner ones as one 32-bit
 * entry (device/qbvh_node.h): the node and the lanes still to visit. A pop takes the next lane
 * of the top entry and removes the entry after its last lane. Instantiated by
 * traversal/qbvh_traverse.h:
 *
 *   #define LT_QBVH_TRAVERSE_NAME  the function to define
 *   #define LT_QBVH_TRAVERSE_BOX4  lt_qbvh_box4 (vector) or lt_qbvh_box4_scalar (plain C)
 *
 * The function traces one ray prepared with lt_ray_prepare (its flags set) through a finished
 * QBVH whose leaves are triangles in leaf order, writes the hit (prim -1 on a miss) and returns
 * 0, or -1 when the stack would overflow (never on a tree of LT_BVH_MAX_DEPTH levels).
 * *deepest grows to the most stack entries the ray held. */

LT_DEVICE int LT_QBVH_TRAVERSE_NAME(LT_GLOBAL const lt_qbvh_node *nodes, LT_GLOBAL const lt_tri *tris,
                                    const lt_ray_setup *r, lt_hit_record *out, lt_trace_counters *c,
                                    lt_i32 *deepest) {
  lt_hit_record hit;
  hit.t = r->tmax, hit.u = hit.v = 0.0f, hit.prim = -1;
  int any_hit = r->flags & LT_QUERY_FLAG_ANY, status = 0;
  lt_qbvh_ray4 q = lt_qbvh_ray4_make(r);
  lt_u32 stack[LT_QBVH_STACK_SIZE];
  lt_i32 sp = 0, node = r->valid ? 0 : -1;
  while (node >= 0) {
    /* The four boxes against the ray, up to the best hit so far; empty lanes drop out. */
    c->traversal_steps++;
    LT_GLOBAL const lt_qbvh_node *n = &nodes[node];
    float t[4];
    int mask = LT_QBVH_TRAVERSE_BOX4(r, &q, n, hit.prim >= 0 ? hit.t : r->tmax, t) & lt_qbvh_child_lanes(n);
    lt_i32 count[4] = {n->count[0], n->count[1], n->count[2], n->count[3]};

    /* One lane or none, the common case of coherent rays: no sorting, no entry. */
    if ((mask & (mask - 1)) == 0) {
      if (mask) {
        int lane = (mask & 1) ? 0 : (mask & 2) ? 1 : (mask & 4) ? 2 : 3;
        if (count[lane] < 0) {
          node = n->first[lane];
          continue;
        }
        lt_qbvh_leaf(tris, r, &hit, n->first[lane], count[lane], c);
        if (any_hit && hit.prim >= 0) break;
      }
      if (sp == 0) break;
      lt_i32 at = lt_qbvh_entry_pop(stack, &sp);
      node = nodes[at >> 2].first[at & 3];
      continue;
    }

    /* Sort the lanes entered near to far; the others get +infinity and sort last (an entered
     * lane's key is at most the largest float, so it never ties with them). */
    float key[4];
    int lane_of[4] = {0, 1, 2, 3};
    for (int i = 0; i < 4; i++) key[i] = (mask >> i & 1) ? (t[i] < LT_FLOAT_MAX ? t[i] : LT_FLOAT_MAX) : INFINITY;
#define LT_QBVH_SWAP(a, b)                                        \
  if (key[b] < key[a]) {                                          \
    float tk = key[a];                                            \
    int tl = lane_of[a];                                          \
    key[a] = key[b], lane_of[a] = lane_of[b];                     \
    key[b] = tk, lane_of[b] = tl;                                 \
  }
    LT_QBVH_SWAP(0, 1)
    LT_QBVH_SWAP(2, 3)
    LT_QBVH_SWAP(0, 2)
    LT_QBVH_SWAP(1, 3)
    LT_QBVH_SWAP(1, 2)
#undef LT_QBVH_SWAP

    /* Leaves now, near to far, until a hit rules out the rest; inner children are kept. */
    int inner[4], m = 0;
    for (int i = 0; i < 4 && key[i] != INFINITY; i++) {
      if (hit.prim >= 0 && key[i] > hit.t) break;
      int lane = lane_of[i];
      if (count[lane] < 0) {
        inner[m++] = lane;
        continue;
      }
      lt_qbvh_leaf(tris, r, &hit, n->first[lane], count[lane], c);
      if (any_hit && hit.prim >= 0) break;
    }
    if (any_hit && hit.prim >= 0) break;

    /* The nearest inner child next; the others as one entry: this node and their lanes, the
     * last repeated (lt_qbvh_entry). */
    if (m > 0) {
      if (m > 1) {
        if (sp == LT_QBVH_STACK_SIZE) {
          status = -1;
          break;
        }
        int o1 = m > 2 ? inner[2] : inner[1];
        stack[sp++] = lt_qbvh_entry(node, inner[1], o1, m > 3 ? inner[3] : o1);
        if (sp > *deepest) *deepest = sp;
      }
      node = n->first[inner[0]];
      continue;
    }

    /* Nothing to go on with here: the next sibling of the top entry. */
    if (sp == 0) break;
    lt_i32 at = lt_qbvh_entry_pop(stack, &sp);
    node = nodes[at >> 2].first[at & 3];
  }
  *out = hit;
  return status;
}

#undef LT_QBVH_TRAVERSE_NAME
#undef LT_QBVH_TRAVERSE_BOX4
