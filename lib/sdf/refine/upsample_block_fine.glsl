// The fine voxels [lo, end) of coarse block @a block (coarseBlockIndex) of a coarse grid of @a coarseDims: those whose
// centres lie in its coarse voxels, read from upsampleBlockFineBegins, which the including shader declares as the
// buffer array fineBegins. UpsampleByBlocksPass writes them; VolumeUpdatePass copies them.
void upsampleBlockFine(uint block, ivec3 coarseDims, out ivec3 lo, out ivec3 end) {
  ivec3 bd = coarseBlockDims(coarseDims);
  ivec3 b = linearCell(block, bd);
  for (int a = 0; a < 3; ++a) {
    int at = upsampleBlockFineAt(bd, a) + b[a];
    lo[a] = fineBegins[at];
    end[a] = fineBegins[at + 1];
  }
}
