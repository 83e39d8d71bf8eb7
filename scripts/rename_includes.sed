# The include paths the per-stage folders changed (one GPU stage in one place: its pass, shaders, the parameters it
# shares with GLSL and its CPU copy). Run over a tree that still uses the old paths:
#   grep -rlE '#include "(gpu/shared|sdf|render)/' lib apps python bench fuzz examples tests |
#     xargs sed -i -f scripts/rename_includes.sed
s#"gpu/shared/Bvh.h"#"bvh/GpuBvhLayout.h"#g
s#"gpu/shared/CoarseSdf.h"#"sdf/coarse/CoarseParams.h"#g
s#"gpu/shared/Refine.h"#"sdf/refine/RefineParams.h"#g
s#"gpu/shared/Render.h"#"render/RenderParams.h"#g
s#"gpu/shared/Compose.h"#"render/compose/ComposeParams.h"#g
s#"sdf/CoarseSdf.h"#"sdf/coarse/CoarseSdf.h"#g
s#"sdf/CoarseMethod.h"#"sdf/coarse/CoarseMethod.h"#g
s#"sdf/CoarseReference.h"#"sdf/coarse/CoarseCpu.h"#g
s#"sdf/GpuSceneBvh.h"#"sdf/scenebvh/GpuSceneBvh.h"#g
s#"sdf/RefinePasses.h"#"sdf/refine/RefinePasses.h"#g
s#"sdf/RefineReference.h"#"sdf/refine/RefineCpu.h"#g
# Split, no single new path: gpu/shared/RenderBindings.h (each stage's bindings are in its render/<stage>/*Params.h;
# all of them come with render/RenderPasses.h, which stays) and render/RenderReference.h (render/<stage>/*Cpu.h:
# SdfShadowCpu, ContactShadowCpu, ShadowMapCpu, TaaCpu, ComposeCpu). Outside the tests nothing included either.
# render/RenderPasses.h keeps its path: it includes every stage's pass header.
