// BVH traversal in GLSL: nearest ray hit and closest point over a two-level BVH (top level over instances
// in world space, bottom levels per mesh in object space). The includer declares these buffers first:
//   BvhNode blasNodes[]; vec4 corners[] (3 per triangle, leaf order); uint triangleIds[];
//   BvhNode tlasNodes[]; uint tlasSlots[]; BvhInstance instances[];
#ifndef RTSDF_BVH_TRAVERSE_GLSL
#define RTSDF_BVH_TRAVERSE_GLSL

#define RTSDF_BVH_STACK 64

// The loop budget of a CPU device's shaders (RTSDF_LOOP_BUDGET > 0, RefineParams.h): lavapipe ends every loop of a
// shader invocation once its subgroup has run 65535 loop iterations in all (one counter shared by every loop of
// the 8 lanes), and then each later loop runs its body once, so that one long walk (a voxel near the centre of a
// finely tessellated sphere is equally near all its triangles: the walk visits the whole tree) silently cut the
// walks and skipped the stores of the other lanes, whichever voxels the refine list's order put beside it. Every walk
// loop here takes a step from the invocation's own budget instead; a lane whose budget is spent ends its walks with
// the nearest found so far (an upper bound of the distance) and sets loopCut, which the caller counts. 8 lanes of
// RTSDF_LOOP_BUDGET steps each stay under the limit with room for the fixed loops.
#ifndef RTSDF_LOOP_BUDGET
#define RTSDF_LOOP_BUDGET 0
#endif
#if RTSDF_LOOP_BUDGET > 0
uint loopBudget = uint(RTSDF_LOOP_BUDGET);
bool loopCut = false;
bool loopStep() {
  if (loopBudget == 0u) {
    loopCut = true;
    return false;
  }
  --loopBudget;
  return true;
}
#define RTSDF_LOOP_STEP loopStep()
// Hide all but a 1/parts share of the budget left, so that the walks until loopRestore(hidden) spend at most that
// share and leave the rest to the work after them (a long walk cannot starve the voxels beside it).
uint loopHide(uint parts) {
  uint hidden = loopBudget - loopBudget / max(parts, 1u);
  loopBudget -= hidden;
  return hidden;
}
void loopRestore(uint hidden) { loopBudget += hidden; }
#else
bool loopCut = false; // never set: no budget
#define RTSDF_LOOP_STEP true
uint loopHide(uint parts) { return 0u; }
void loopRestore(uint hidden) {}
#endif

uint nodeFirst(BvhNode n) { return floatBitsToUint(n.lo.w); }
uint nodeCount(BvhNode n) { return floatBitsToUint(n.hi.w); }

// The top-level walk that traceNearest, occludedWithin, closestPoint and the refinement's cell search share: depth
// first from the root of tlasNodes, a popped node NODE skipped when the expression CULLED (of NODE and the
// caller's locals) is true, so a nearer hit found meanwhile prunes it; an inner node pushes its children (the
// first on top); a leaf runs the code between the two macros once per instance, declared as 'BvhInstance INST'
// (its index in instances[]: tlasSlot). Macros, not a function: GLSL has no callbacks, the body updates the
// caller's locals, and the loops stay exactly the hand-written ones (no extra iterations; lavapipe cuts long
// loops). Use: RTSDF_TLAS_WALK_BEGIN(tn, cull, inst) ... RTSDF_TLAS_WALK_END
#define RTSDF_TLAS_WALK_BEGIN(NODE, CULLED, INST)                                                                      \
  uint tstack[RTSDF_BVH_STACK];                                                                                        \
  int tsp = 0;                                                                                                         \
  tstack[tsp++] = 0u;                                                                                                  \
  while (tsp > 0 && RTSDF_LOOP_STEP) {                                                                                 \
    /* Inner nodes until a leaf, so that SIMD lanes enter their instances together (while-while). */                  \
    uint tlasFirst = 0u, tc = 0u;                                                                                      \
    while (tsp > 0 && RTSDF_LOOP_STEP) {                                                                               \
      BvhNode NODE = tlasNodes[tstack[--tsp]];                                                                         \
      if (CULLED) continue;                                                                                            \
      if (nodeCount(NODE) != 0u) {                                                                                     \
        tlasFirst = nodeFirst(NODE);                                                                                   \
        tc = nodeCount(NODE);                                                                                          \
        break;                                                                                                         \
      }                                                                                                                \
      tstack[tsp++] = nodeFirst(NODE) + 1u;                                                                            \
      tstack[tsp++] = nodeFirst(NODE);                                                                                 \
    }                                                                                                                  \
    for (uint ti = 0u; ti < tc && RTSDF_LOOP_STEP; ++ti) {                                                             \
      uint tlasSlot = tlasSlots[tlasFirst + ti];                                                                       \
      BvhInstance INST = instances[tlasSlot];
#define RTSDF_TLAS_WALK_END                                                                                            \
    }                                                                                                                  \
  }

vec3 xformPoint(vec4 m[3], vec3 p) { return vec3(dot(m[0].xyz, p) + m[0].w, dot(m[1].xyz, p) + m[1].w, dot(m[2].xyz, p) + m[2].w); }
vec3 xformVector(vec4 m[3], vec3 v) { return vec3(dot(m[0].xyz, v), dot(m[1].xyz, v), dot(m[2].xyz, v)); }

// Entry distance of the ray into the box, or +inf when it misses [tmin, tmax].
float rayBox(vec3 o, vec3 invD, vec3 lo, vec3 hi, float tmin, float tmax) {
  vec3 t0 = (lo - o) * invD, t1 = (hi - o) * invD;
  vec3 tn = min(t0, t1), tf = max(t0, t1);
  float a = max(max(tn.x, tn.y), max(tn.z, tmin));
  float b = min(min(tf.x, tf.y), min(tf.z, tmax));
  return a <= b ? a : 1.0 / 0.0;
}

// Moller-Trumbore; updates t and returns true on a nearer hit in (tmin, t). front: the ray arrives on the
// side the counter-clockwise normal points to.
bool rayTriangle(vec3 o, vec3 d, vec3 a, vec3 b, vec3 c, float tmin, inout float t, out bool front) {
  vec3 e1 = b - a, e2 = c - a;
  vec3 pv = cross(d, e2);
  float det = dot(e1, pv);
  front = det > 0.0; // det = -dot(d, cross(e1, e2)): positive when the ray opposes the normal
  if (det == 0.0) return false;
  float inv = 1.0 / det;
  vec3 tv = o - a;
  float u = dot(tv, pv) * inv;
  if (u < 0.0 || u > 1.0) return false;
  vec3 qv = cross(tv, e1);
  float v = dot(d, qv) * inv;
  if (v < 0.0 || u + v > 1.0) return false;
  float th = dot(e2, qv) * inv;
  if (th <= tmin || th >= t) return false;
  t = th;
  return true;
}

// Ray o + t d in instance inst's object space (t unchanged: the direction is not normalized) and its inverse direction.
void objectRay(BvhInstance inst, vec3 o, vec3 d, out vec3 oo, out vec3 dd, out vec3 invDD) {
  oo = xformPoint(inst.worldToObject, o);
  dd = xformVector(inst.worldToObject, d);
  invDD = 1.0 / dd;
}

// Nearest hit along o + t d, t in (tmin, tmax). Returns false when nothing is hit.
bool traceNearest(vec3 o, vec3 d, float tmin, float tmax, out BvhHit hit) {
  hit.point = vec4(0.0, 0.0, 0.0, -1.0);
  hit.instance = 0u; hit.triangle = 0u; hit.frontFace = 0u; hit.leaf = 0u;
  float best = tmax;
  bool found = false;
  vec3 invD = 1.0 / d;
  RTSDF_TLAS_WALK_BEGIN(tn, isinf(rayBox(o, invD, tn.lo.xyz, tn.hi.xyz, tmin, best)), inst)
    vec3 oo, dd, invDD;
    objectRay(inst, o, d, oo, dd, invDD);
    uint stack[RTSDF_BVH_STACK];
    int sp = 0;
    stack[sp++] = inst.blasRoot;
    while (sp > 0 && RTSDF_LOOP_STEP) {
      // Inner nodes until a leaf, then its triangles: SIMD lanes test theirs together (while-while).
      uint leafFirst = 0u, cnt = 0u;
      while (sp > 0 && RTSDF_LOOP_STEP) {
        BvhNode n = blasNodes[stack[--sp]];
        if (isinf(rayBox(oo, invDD, n.lo.xyz, n.hi.xyz, tmin, best))) continue;
        if (nodeCount(n) != 0u) {
          leafFirst = nodeFirst(n);
          cnt = nodeCount(n);
          break;
        }
        // Visit the nearer child first.
        BvhNode l = blasNodes[nodeFirst(n)], r = blasNodes[nodeFirst(n) + 1u];
        float tl = rayBox(oo, invDD, l.lo.xyz, l.hi.xyz, tmin, best);
        float tr = rayBox(oo, invDD, r.lo.xyz, r.hi.xyz, tmin, best);
        if (tl <= tr) { if (!isinf(tr)) stack[sp++] = nodeFirst(n) + 1u; if (!isinf(tl)) stack[sp++] = nodeFirst(n); }
        else { if (!isinf(tl)) stack[sp++] = nodeFirst(n); if (!isinf(tr)) stack[sp++] = nodeFirst(n) + 1u; }
      }
      for (uint k = 0u; k < cnt && RTSDF_LOOP_STEP; ++k) {
        uint tri = leafFirst + k;
        bool front;
        if (rayTriangle(oo, dd, corners[3u * tri].xyz, corners[3u * tri + 1u].xyz, corners[3u * tri + 2u].xyz, tmin,
                        best, front)) {
          found = true;
          hit.instance = inst.instanceId;
          hit.triangle = triangleIds[tri];
          hit.leaf = tri;
          hit.frontFace = (front != (inst.mirrored != 0u)) ? 1u : 0u;
        }
      }
    }
  RTSDF_TLAS_WALK_END
  if (found) hit.point = vec4(o + best * d, best);
  return found;
}

// Whether anything lies on o + t d for t in (0, tmax): any hit ends the walk (shadow rays need no nearest one).
bool occludedWithin(vec3 o, vec3 d, float tmax) {
  bool blocked = false;
  vec3 invD = 1.0 / d;
  RTSDF_TLAS_WALK_BEGIN(tn, blocked || isinf(rayBox(o, invD, tn.lo.xyz, tn.hi.xyz, 0.0, tmax)), inst)
    vec3 oo, dd, invDD;
    objectRay(inst, o, d, oo, dd, invDD);
    uint stack[RTSDF_BVH_STACK];
    int sp = 0;
    stack[sp++] = inst.blasRoot;
    while (sp > 0 && !blocked && RTSDF_LOOP_STEP) {
      BvhNode n = blasNodes[stack[--sp]];
      if (isinf(rayBox(oo, invDD, n.lo.xyz, n.hi.xyz, 0.0, tmax))) continue;
      uint cnt = nodeCount(n);
      if (cnt == 0u) {
        stack[sp++] = nodeFirst(n) + 1u;
        stack[sp++] = nodeFirst(n);
        continue;
      }
      for (uint k = 0u; k < cnt && !blocked && RTSDF_LOOP_STEP; ++k) {
        uint tri = nodeFirst(n) + k;
        float t = tmax;
        bool front;
        blocked = rayTriangle(oo, dd, corners[3u * tri].xyz, corners[3u * tri + 1u].xyz, corners[3u * tri + 2u].xyz,
                              0.0, t, front);
      }
    }
  RTSDF_TLAS_WALK_END
  return blocked;
}

// Closest point on segment ab to p (a point when a == b).
vec3 closestOnSegment(vec3 p, vec3 a, vec3 b) {
  vec3 ab = b - a;
  float l2 = dot(ab, ab);
  float t = l2 > 0.0 ? clamp(dot(p - a, ab) / l2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection 5.1.5).
// Slivers: rounding can skip every vertex and edge region yet leave a barycentric weight negative (or their
// sum zero), which put the "face" point off the triangle, nearer than the true distance. The face point is
// taken only when all three weights are positive and their sum is a normal number; otherwise the nearest of
// the three edges, which for such a thin triangle is the answer to within rounding. The face point is the
// projection onto the plane: the vertex tests (well-conditioned dot products) have already refused points
// beyond the corners, so when the weights are noise the projection lies within rounding of the triangle.
vec3 closestOnTriangle(vec3 p, vec3 a, vec3 b, vec3 c) {
  vec3 ab = b - a, ac = c - a, ap = p - a;
  float d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  vec3 bp = p - b;
  float d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  vec3 cp = p - c;
  float d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  float va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  float sum = va + vb + vc;
  vec3 n = cross(ab, ac);
  float nn = dot(n, n);
  if (va > 0.0 && vb > 0.0 && vc > 0.0 && sum >= 1.17549435e-38 && !isinf(sum) && nn >= 1.17549435e-38 && !isinf(nn))
    // p projected onto the plane, not a + ab vb/sum + ac vc/sum: on a sliver the weights are differences of
    // nearly equal products (noise when p projects onto an edge), the projection is not.
    return p - n * (dot(ap, n) / nn);
  vec3 qab = closestOnSegment(p, a, b), qbc = closestOnSegment(p, b, c), qca = closestOnSegment(p, c, a);
  float dab = dot(p - qab, p - qab), dbc = dot(p - qbc, p - qbc), dca = dot(p - qca, p - qca);
  return dab <= dbc ? (dab <= dca ? qab : qca) : (dbc <= dca ? qbc : qca);
}

// A closest-point query in progress: the nearest triangle so far and the tie rule's state. closestPoint walks
// the BVH with it; the refinement's per-cell candidates (refine_main.glsl) test a short list with it, so both
// give the same answer from the same triangles.
struct ClosestQuery {
  vec3 p;          // the query point (world)
  float best;      // distance of the nearest triangle so far (the search radius until one is found)
  float ulp4;      // 4 float ulps at p's coordinates
  float facing;    // |cos| between p - q and the best triangle's normal
  vec3 point;      // the closest point so far
  bool found;
  uint instance, triangle, front, leaf;
};

ClosestQuery closestBegin(vec3 p, float maxDist) {
  ClosestQuery s;
  s.p = p;
  s.best = maxDist;
  // Ties (below) must be seen: culling keeps boxes within rounding of the best distance.
  s.ulp4 = 4.8e-7 * max(abs(p.x), max(abs(p.y), abs(p.z)));
  s.facing = -1.0;
  s.point = vec3(0.0);
  s.found = false;
  s.instance = 0u; s.triangle = 0u; s.front = 0u; s.leaf = 0u;
  return s;
}

// How far a box or triangle may lie from p and still hold a nearer point or a tie.
float closestReach(ClosestQuery s) { return s.best * (1.0 + 1.0e-5) + s.ulp4; }

// Test triangle abc (world space; leaf: its leaf-order index, of instance 'instanceId', 'mirrored' as that
// instance's transform) against the query.
void closestTriangle(inout ClosestQuery s, vec3 a, vec3 b, vec3 c, uint mirrored, uint instanceId, uint leaf) {
  vec3 q = closestOnTriangle(s.p, a, b, c);
  float dist = length(s.p - q);
  if (dist > closestReach(s)) return; // neither nearer nor a tie: the common case
  // Triangles sharing the closest edge or vertex are equally near (to rounding); the sign comes from
  // the one whose plane p lies most squarely off: near a sharp edge the other face's plane can pass
  // within rounding of p, and its side test would be a coin toss.
  vec3 nrm = cross(b - a, c - a);
  float nl = length(nrm);
  float facing = (dist > 0.0 && nl > 0.0) ? abs(dot(s.p - q, nrm)) / (dist * nl) : 0.0;
  // A tie is the same distance and closest point (a shared edge or vertex) to rounding. The point
  // slides along a shared edge by more than the distance changes, and off it, onto the face of a triangle
  // beside, by up to sqrt(2e-5) = 4.5e-3 of the distance while the distances still tie within 1e-5 (p
  // almost in the plane of one face and squarely off the other: 1e-3 missed such ties on the thin
  // leaves of the default scene and took the in-plane face's side, 2.7 voxels inside at fine 256).
  bool tie = s.found && abs(dist - s.best) <= 1.0e-5 * s.best + s.ulp4 &&
             length(q - s.point) <= 1.0e-2 * s.best + 2.0 * s.ulp4;
  // Outside when p lies on the side the triangle's counter-clockwise normal points to.
  uint front = dot(s.p - q, nrm) * (mirrored != 0u ? -1.0 : 1.0) >= 0.0 ? 1u : 0u;
  // The point and distance are the nearest's; in a tie only the side may come from another triangle.
  if (tie && facing > s.facing) {
    s.facing = facing;
    s.front = front;
  }
  if (dist < s.best) {
    s.best = dist;
    s.found = true;
    s.point = q;
    s.instance = instanceId;
    s.triangle = triangleIds[leaf];
    s.leaf = leaf;
    if (!tie) {
      s.facing = facing;
      s.front = front;
    }
  }
}

// The facing (ClosestQuery::facing) of the last answer closestEnd gave: how squarely off the triangle that gave its side
// the point lies (0: in its plane, where the side is a coin toss).
float closestFacing = 0.0;

// The query's answer: false when no triangle lies within its radius.
bool closestEnd(ClosestQuery s, out BvhHit hit) {
  closestFacing = s.facing;
  hit.point = s.found ? vec4(s.point, s.best) : vec4(0.0, 0.0, 0.0, -1.0);
  hit.instance = s.instance;
  hit.triangle = s.triangle;
  hit.frontFace = s.front; // closest points: 1 when p is on the outer side of the closest triangle
  hit.leaf = s.leaf;
  return s.found;
}

// Triangle 'leaf' of instance 'inst' in world space.
void worldTriangle(BvhInstance inst, uint leaf, out vec3 a, out vec3 b, out vec3 c) {
  a = xformPoint(inst.objectToWorld, corners[3u * leaf].xyz);
  b = xformPoint(inst.objectToWorld, corners[3u * leaf + 1u].xyz);
  c = xformPoint(inst.objectToWorld, corners[3u * leaf + 2u].xyz);
}

// The bottom-level walk of a point query (closestPoint, the refinement's cell search): instance INST's nodes depth
// first from object-space point PO, nearer child first; a node farther than REACH (an expression, read again at
// every node, in world units: world distance >= minScale * object distance, a conservative cull) is skipped, and so
// is a child for which the function SKIPPED(po, lo, hi, minScale) is true; the walk goes on while GOING holds. The
// code between the macros runs per triangle, its leaf index declared as 'uint LEAF'.
// Use: RTSDF_POINT_WALK_BEGIN(inst, po, reach, skipped, going, leaf) ... RTSDF_POINT_WALK_END
// Two shapes, the same nodes in the same order: with RTSDF_POINT_WALK_WHILE_WHILE (the shaders for CPU devices) inner
// nodes are descended until a leaf before its triangles are tested, so that the SIMD lanes of a CPU test theirs
// together (lavapipe runs a branch's code, masked, whenever any lane takes it); without it (GPUs), one node per step.
// Measured: docs/results.md, "Closest mode's first frame: 4-5x on lavapipe, and what the same changes did on an
// NVIDIA H200".
#ifndef RTSDF_POINT_WALK_WHILE_WHILE
#define RTSDF_POINT_WALK_WHILE_WHILE 0
#endif
// The point walks' inner node N: push its children within REACH (a float) that SKIPPED keeps, the nearer on top.
#define RTSDF_POINT_WALK_PUSH_CHILDREN(INST, PO, SKIPPED, N, REACH)                                                    \
  {                                                                                                                    \
    BvhNode l = blasNodes[nodeFirst(N)], r = blasNodes[nodeFirst(N) + 1u];                                             \
    float dl = INST.minScale * boxDistance(PO, l.lo.xyz, l.hi.xyz);                                                    \
    float dr = INST.minScale * boxDistance(PO, r.lo.xyz, r.hi.xyz);                                                    \
    bool keepL = dl <= (REACH) && !SKIPPED(PO, l.lo.xyz, l.hi.xyz, INST.minScale);                                    \
    bool keepR = dr <= (REACH) && !SKIPPED(PO, r.lo.xyz, r.hi.xyz, INST.minScale);                                    \
    if (dl <= dr ? keepR : keepL) stack[sp++] = dl <= dr ? nodeFirst(N) + 1u : nodeFirst(N);                           \
    if (dl <= dr ? keepL : keepR) stack[sp++] = dl <= dr ? nodeFirst(N) : nodeFirst(N) + 1u;                           \
  }
#if RTSDF_POINT_WALK_WHILE_WHILE
#define RTSDF_POINT_WALK_BEGIN(INST, PO, REACH, SKIPPED, GOING, LEAF)                                                  \
  uint stack[RTSDF_BVH_STACK];                                                                                         \
  int sp = 0;                                                                                                          \
  stack[sp++] = INST.blasRoot;                                                                                         \
  while (sp > 0 && (GOING) && RTSDF_LOOP_STEP) {                                                                       \
    /* Inner nodes until a leaf: the lanes of a SIMD machine then test their triangles together (while-while). */     \
    uint leafFirst = 0u, leafCount = 0u;                                                                               \
    while (sp > 0 && RTSDF_LOOP_STEP) {                                                                                \
      BvhNode n = blasNodes[stack[--sp]];                                                                              \
      float reach = (REACH);                                                                                           \
      if (INST.minScale * boxDistance(PO, n.lo.xyz, n.hi.xyz) > reach) continue;                                       \
      if (nodeCount(n) != 0u) {                                                                                        \
        leafFirst = nodeFirst(n);                                                                                      \
        leafCount = nodeCount(n);                                                                                      \
        break;                                                                                                         \
      }                                                                                                                \
      RTSDF_POINT_WALK_PUSH_CHILDREN(INST, PO, SKIPPED, n, reach)                                                      \
    }                                                                                                                  \
    for (uint k = 0u; k < leafCount && RTSDF_LOOP_STEP; ++k) {                                                         \
      uint LEAF = leafFirst + k;
#else
#define RTSDF_POINT_WALK_BEGIN(INST, PO, REACH, SKIPPED, GOING, LEAF)                                                  \
  uint stack[RTSDF_BVH_STACK];                                                                                         \
  int sp = 0;                                                                                                          \
  stack[sp++] = INST.blasRoot;                                                                                         \
  while (sp > 0 && (GOING) && RTSDF_LOOP_STEP) {                                                                       \
    BvhNode n = blasNodes[stack[--sp]];                                                                                \
    float reach = (REACH);                                                                                             \
    if (INST.minScale * boxDistance(PO, n.lo.xyz, n.hi.xyz) > reach) continue;                                         \
    uint leafFirst = nodeFirst(n), leafCount = nodeCount(n);                                                           \
    if (leafCount == 0u) {                                                                                             \
      RTSDF_POINT_WALK_PUSH_CHILDREN(INST, PO, SKIPPED, n, reach)                                                      \
      continue;                                                                                                        \
    }                                                                                                                  \
    for (uint k = 0u; k < leafCount && RTSDF_LOOP_STEP; ++k) {                                                         \
      uint LEAF = leafFirst + k;
#endif
#define RTSDF_POINT_WALK_END                                                                                           \
    }                                                                                                                  \
  }

// The SKIPPED of a point walk that culls by distance alone.
bool noNodeSkipped(vec3 po, vec3 lo, vec3 hi, float scale) { return false; }

// Closest surface point to p within maxDist (world space). Returns false when none is that close.
bool closestPoint(vec3 p, float maxDist, out BvhHit hit) {
  ClosestQuery s = closestBegin(p, maxDist);
  RTSDF_TLAS_WALK_BEGIN(tn, boxDistance(p, tn.lo.xyz, tn.hi.xyz) > closestReach(s), inst)
    vec3 po = xformPoint(inst.worldToObject, p);
    RTSDF_POINT_WALK_BEGIN(inst, po, closestReach(s), noNodeSkipped, true, leaf)
      vec3 a, b, c;
      worldTriangle(inst, leaf, a, b, c);
      closestTriangle(s, a, b, c, inst.mirrored, inst.instanceId, leaf);
    RTSDF_POINT_WALK_END
  RTSDF_TLAS_WALK_END
  return closestEnd(s, hit);
}

#endif
