// The scene BVH's buffers at the bindings bvh/GpuBvhLayout.h names (GpuSceneBvh binds them), for the shaders
// that include bvh_traverse.glsl. Include after bvh/GpuBvhLayout.h.
layout(std430, binding = kBvhBindingBlasNodes) readonly buffer BlasNodes { BvhNode blasNodes[]; };
layout(std430, binding = kBvhBindingCorners) readonly buffer Corners { vec4 corners[]; };
layout(std430, binding = kBvhBindingTriangleIds) readonly buffer TriangleIds { uint triangleIds[]; };
layout(std430, binding = kBvhBindingTlasNodes) readonly buffer TlasNodes { BvhNode tlasNodes[]; };
layout(std430, binding = kBvhBindingTlasSlots) readonly buffer TlasSlots { uint tlasSlots[]; };
layout(std430, binding = kBvhBindingInstances) readonly buffer Instances { BvhInstance instances[]; };
