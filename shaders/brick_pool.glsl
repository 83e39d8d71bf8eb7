// The brick pool's pages (the sparse fine state, gpu/shared/Refine.h): the includer defines RTSDF_VALUE_PAGES (the
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
RTSDF_POOL_PAGE(values, float, RTSDF_VALUE_PAGES, 0)
RTSDF_POOL_PAGE(values, float, RTSDF_VALUE_PAGES, 1)
RTSDF_POOL_PAGE(values, float, RTSDF_VALUE_PAGES, 2)
RTSDF_POOL_PAGE(values, float, RTSDF_VALUE_PAGES, 3)

// Where fine value @a local of brick slot @a slot lies in its page.
uint poolOffset(uint slot, uint local) { return (slot % RTSDF_POOL_PARAMS.pageBricks) * kBrickVoxels + local; }

float loadValue(uint slot, uint local) {
  uint page = slot / RTSDF_POOL_PARAMS.pageBricks, at = poolOffset(slot, local);
  if (page == 0u) return values0[at];
  if (page == 1u) return values1[at];
  if (page == 2u) return values2[at];
  return values3[at];
}

#ifndef RTSDF_POOL_READONLY
void storeValue(uint slot, uint local, float v) {
  uint page = slot / RTSDF_POOL_PARAMS.pageBricks, at = poolOffset(slot, local);
  if (page == 0u) values0[at] = v;
  else if (page == 1u) values1[at] = v;
  else if (page == 2u) values2[at] = v;
  else values3[at] = v;
}
#endif

#ifdef RTSDF_VOTE_PAGES
RTSDF_POOL_PAGE(votes, uint, RTSDF_VOTE_PAGES, 0)
RTSDF_POOL_PAGE(votes, uint, RTSDF_VOTE_PAGES, 1)
RTSDF_POOL_PAGE(votes, uint, RTSDF_VOTE_PAGES, 2)
RTSDF_POOL_PAGE(votes, uint, RTSDF_VOTE_PAGES, 3)

uint loadVotes(uint slot, uint local) {
  uint page = slot / RTSDF_POOL_PARAMS.pageBricks, at = poolOffset(slot, local);
  if (page == 0u) return votes0[at];
  if (page == 1u) return votes1[at];
  if (page == 2u) return votes2[at];
  return votes3[at];
}

void storeVotes(uint slot, uint local, uint v) {
  uint page = slot / RTSDF_POOL_PARAMS.pageBricks, at = poolOffset(slot, local);
  if (page == 0u) votes0[at] = v;
  else if (page == 1u) votes1[at] = v;
  else if (page == 2u) votes2[at] = v;
  else votes3[at] = v;
}
#endif
