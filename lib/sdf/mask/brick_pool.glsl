// The brick pool's pages (the sparse fine state, sdf/mask/MaskParams.h): the includer defines RTSDF_VALUE_PAGES (the
// binding of page 0 of the values), optionally RTSDF_VOTE_PAGES (of the votes), RTSDF_POOL_READONLY (no stores)
// and RTSDF_POOL_PARAMS (a RefineParams holding pageBricks; default: params). A slot's values live in page
// slot / pageBricks: GLSL selects a page by branching, so no descriptor indexing is needed.
#ifndef RTSDF_POOL_PARAMS
#define RTSDF_POOL_PARAMS params
#endif
#ifdef RTSDF_POOL_READONLY
#define RTSDF_POOL_ACCESS readonly
#else
#define RTSDF_POOL_ACCESS
#endif
#define RTSDF_POOL_PAGE(KIND, TYPE, BASE, N) \
  layout(std430, binding = BASE + N) RTSDF_POOL_ACCESS buffer KIND##Page##N { TYPE KIND##N[]; };

// Where fine value @a local of brick slot @a slot lies in its page.
uint poolOffset(uint slot, uint local) { return (slot % RTSDF_POOL_PARAMS.pageBricks) * kBrickVoxels + local; }

// LOAD(slot, local) reads pages KIND0..3 of TYPE.
#define RTSDF_POOL_LOAD(KIND, TYPE, LOAD)                                       \
  TYPE LOAD(uint slot, uint local) {                                            \
    uint page = slot / RTSDF_POOL_PARAMS.pageBricks, at = poolOffset(slot, local); \
    if (page == 0u) return KIND##0[at];                                         \
    if (page == 1u) return KIND##1[at];                                         \
    if (page == 2u) return KIND##2[at];                                         \
    return KIND##3[at];                                                         \
  }
// STORE(slot, local, v) writes them.
#define RTSDF_POOL_STORE(KIND, TYPE, STORE)                                     \
  void STORE(uint slot, uint local, TYPE v) {                                   \
    uint page = slot / RTSDF_POOL_PARAMS.pageBricks, at = poolOffset(slot, local); \
    if (page == 0u) KIND##0[at] = v;                                            \
    else if (page == 1u) KIND##1[at] = v;                                       \
    else if (page == 2u) KIND##2[at] = v;                                       \
    else KIND##3[at] = v;                                                       \
  }

RTSDF_POOL_PAGE(values, float, RTSDF_VALUE_PAGES, 0)
RTSDF_POOL_PAGE(values, float, RTSDF_VALUE_PAGES, 1)
RTSDF_POOL_PAGE(values, float, RTSDF_VALUE_PAGES, 2)
RTSDF_POOL_PAGE(values, float, RTSDF_VALUE_PAGES, 3)
RTSDF_POOL_LOAD(values, float, loadValue)
#ifndef RTSDF_POOL_READONLY
RTSDF_POOL_STORE(values, float, storeValue)
#endif

#ifdef RTSDF_VOTE_PAGES
RTSDF_POOL_PAGE(votes, uint, RTSDF_VOTE_PAGES, 0)
RTSDF_POOL_PAGE(votes, uint, RTSDF_VOTE_PAGES, 1)
RTSDF_POOL_PAGE(votes, uint, RTSDF_VOTE_PAGES, 2)
RTSDF_POOL_PAGE(votes, uint, RTSDF_VOTE_PAGES, 3)
RTSDF_POOL_LOAD(votes, uint, loadVotes)
RTSDF_POOL_STORE(votes, uint, storeVotes)
#endif
