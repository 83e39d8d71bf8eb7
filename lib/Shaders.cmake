# The GLSL compute shaders, compiled by glslc at build time and embedded into rtsdf_shaders (never commit SPIR-V),
# each looked up by its embedded name (gpu::embeddedShader). A shader's source lies in the folder of its stage,
# beside its pass; a variant is the same source compiled with other defines, so every variant is one row here.
# Row: embedded name, source (relative to lib/; a .glsl source is compiled as a compute shader), defines (a row may
# go on over lines).
add_library(rtsdf_shaders STATIC)
target_include_directories(rtsdf_shaders PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
set(closest RTSDF_REFINE_MODE=RTSDF_REFINE_CLOSEST)
rtsdf_add_shaders(TARGET rtsdf_shaders ROOT ${CMAKE_CURRENT_SOURCE_DIR} SHADERS
  # The gpu layer's own (VulkanContext's smoke test).
  "fill.comp                      gpu/shared/fill.comp"
  # The coarse SDF.
  "voxelize_clear.comp            sdf/coarse/voxelize_clear.comp"
  "voxelize_chunks.comp           sdf/coarse/voxelize_chunks.comp"
  "voxelize.comp                  sdf/coarse/voxelize.comp"
  "jump_flood.comp                sdf/coarse/jump_flood.comp"
  "exact_edt.comp                 sdf/coarse/exact_edt.comp"
  "coarse_distance.comp           sdf/coarse/coarse_distance.comp"
  "coarse_region.comp             sdf/coarse/coarse_region.comp"
  "seed_shift.comp                sdf/coarse/seed_shift.comp"
  # The scene BVH's queries (tests).
  "bvh_query.comp                 sdf/scenebvh/bvh_query.comp"
  # The refinement: UpsamplePass's two kernels and its kernel over listed blocks (UpsampleBlocksPass lists them),
  # RayRefinePass, ClosestRefinePass::Variant's eight shaders (sign from rays or the closest side, search per voxel
  # or per cell, the BVH walk for GPUs or CPU devices).
  "refine_upsample.comp           sdf/refine/refine_upsample_main.glsl  RTSDF_UPSAMPLE_RUN=RTSDF_UPSAMPLE_RUN_LENGTH"
  "refine_upsample_voxel.comp     sdf/refine/refine_upsample_main.glsl  RTSDF_UPSAMPLE_RUN=1"
  "refine_upsample_blocks.comp    sdf/refine/refine_upsample_main.glsl  RTSDF_UPSAMPLE_RUN=RTSDF_UPSAMPLE_RUN_LENGTH
                                  RTSDF_UPSAMPLE_BLOCKS=1"
  "upsample_blocks.comp           sdf/refine/upsample_blocks.comp"
  "refine_rays.comp               sdf/refine/refine_main.glsl  RTSDF_REFINE_MODE=RTSDF_REFINE_RAYS"
  "refine_closest.comp            sdf/refine/refine_main.glsl  ${closest}
                                  RTSDF_CELL_SEARCH=0 RTSDF_SIGN_RAYS=1 RTSDF_POINT_WALK_WHILE_WHILE=0"
  "refine_closest_side.comp       sdf/refine/refine_main.glsl  ${closest}
                                  RTSDF_CELL_SEARCH=0 RTSDF_SIGN_RAYS=0 RTSDF_POINT_WALK_WHILE_WHILE=0"
  "refine_closest_cell.comp       sdf/refine/refine_main.glsl  ${closest}
                                  RTSDF_CELL_SEARCH=1 RTSDF_SIGN_RAYS=1 RTSDF_POINT_WALK_WHILE_WHILE=0"
  "refine_closest_cell_side.comp  sdf/refine/refine_main.glsl  ${closest}
                                  RTSDF_CELL_SEARCH=1 RTSDF_SIGN_RAYS=0 RTSDF_POINT_WALK_WHILE_WHILE=0"
  "refine_closest_cpu.comp        sdf/refine/refine_main.glsl  ${closest}
                                  RTSDF_CELL_SEARCH=0 RTSDF_SIGN_RAYS=1 RTSDF_POINT_WALK_WHILE_WHILE=1
                                  RTSDF_LOOP_BUDGET=RTSDF_CPU_LOOP_BUDGET"
  "refine_closest_side_cpu.comp   sdf/refine/refine_main.glsl  ${closest}
                                  RTSDF_CELL_SEARCH=0 RTSDF_SIGN_RAYS=0 RTSDF_POINT_WALK_WHILE_WHILE=1
                                  RTSDF_LOOP_BUDGET=RTSDF_CPU_LOOP_BUDGET"
  "refine_closest_cell_cpu.comp   sdf/refine/refine_main.glsl  ${closest}
                                  RTSDF_CELL_SEARCH=1 RTSDF_SIGN_RAYS=1 RTSDF_POINT_WALK_WHILE_WHILE=1
                                  RTSDF_LOOP_BUDGET=RTSDF_CPU_LOOP_BUDGET"
  "refine_closest_cell_side_cpu.comp  sdf/refine/refine_main.glsl  ${closest}
                                  RTSDF_CELL_SEARCH=1 RTSDF_SIGN_RAYS=0 RTSDF_POINT_WALK_WHILE_WHILE=1
                                  RTSDF_LOOP_BUDGET=RTSDF_CPU_LOOP_BUDGET"
  # The exact winding number of the voxels the closest shaders' walks left near 1/2 (WindingExactPass).
  "winding_exact.comp             sdf/refine/winding_exact.comp"
  # The ray mask and the brick pool.
  "mask_compact.comp              sdf/mask/mask_compact.comp"
  "mask_compact_blocks.comp       sdf/mask/mask_compact.comp  RTSDF_MASK_BLOCK_LIST=1"
  "mask_dispatch.comp             sdf/mask/mask_dispatch.comp"
  "mask_region.comp               sdf/mask/mask_region.comp"
  "mask_leave.comp                sdf/mask/mask_leave.comp"
  "brick_alloc.comp               sdf/mask/brick_alloc.comp"
  # A scrolled level's grids moved by whole cells.
  "grid_shift.comp                sdf/pipeline/grid_shift.comp"
  # The renderer.
  "gbuffer.comp                   render/gbuffer/gbuffer.comp"
  "contact_shadow.comp            render/contactshadow/contact_shadow.comp"
  "sdf_shadow.comp                render/sdfshadow/sdf_shadow_main.glsl  RTSDF_SHADOW_FIELD_TEXTURE"
  "sdf_shadow_buffer.comp         render/sdfshadow/sdf_shadow_main.glsl  RTSDF_SHADOW_FIELD_BUFFER"
  "sdf_shadow_umbra.comp          render/sdfshadow/sdf_shadow_main.glsl  RTSDF_SHADOW_FIELD_TEXTURE RTSDF_SHADOW_UMBRA"
  "sdf_shadow_umbra_buffer.comp   render/sdfshadow/sdf_shadow_main.glsl  RTSDF_SHADOW_FIELD_BUFFER RTSDF_SHADOW_UMBRA"
  "sdf_shadow_bricks.comp         render/sdfshadow/sdf_shadow_main.glsl  RTSDF_SHADOW_FIELD_BRICKS"
  "sdf_shadow_umbra_bricks.comp   render/sdfshadow/sdf_shadow_main.glsl  RTSDF_SHADOW_FIELD_BRICKS RTSDF_SHADOW_UMBRA"
  "sdf_shadow_cascade4.comp       render/sdfshadow/sdf_shadow_main.glsl  RTSDF_SHADOW_FIELD_CASCADE RTSDF_CASCADE_CASES=4"
  "sdf_shadow_cascade.comp        render/sdfshadow/sdf_shadow_main.glsl  RTSDF_SHADOW_FIELD_CASCADE RTSDF_CASCADE_CASES=10"
  "sdf_shadow_umbra_cascade4.comp render/sdfshadow/sdf_shadow_main.glsl  RTSDF_SHADOW_FIELD_CASCADE RTSDF_SHADOW_UMBRA RTSDF_CASCADE_CASES=4"
  "sdf_shadow_umbra_cascade.comp  render/sdfshadow/sdf_shadow_main.glsl  RTSDF_SHADOW_FIELD_CASCADE RTSDF_SHADOW_UMBRA RTSDF_CASCADE_CASES=10"
  "volume_fill.comp               render/sdfshadow/volume_fill.comp"
  "volume_update_blocks.comp      render/sdfshadow/volume_update_main.glsl  RTSDF_VOLUME_UPDATE_REFINED=0"
  "volume_update_refined.comp     render/sdfshadow/volume_update_main.glsl  RTSDF_VOLUME_UPDATE_REFINED=1"
  "shadow_map.comp                render/shadowmap/shadow_map.comp"
  "shadow_lookup.comp             render/shadowmap/shadow_lookup.comp"
  "taa.comp                       render/taa/taa.comp"
  "compose.comp                   render/compose/compose.comp"
)
unset(closest)
