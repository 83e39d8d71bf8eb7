#pragma once
/// @file RenderPasses.h
/// @brief The renderer's GPU passes, each a small named unit (inputs, outputs, execute) in the folder of its stage
///        with its shaders, the parameters it shares with them and its CPU copy: GBufferPass (gbuffer/),
///        SdfShadowPass and VolumeFillPass (sdfshadow/), ContactShadowPass (contactshadow/), ShadowMapPass
///        (shadowmap/), TaaPass (taa/), ComposePass (compose/). Included whole by the renderer.
#include "render/compose/ComposePass.h"
#include "render/contactshadow/ContactShadowPass.h"
#include "render/gbuffer/GBufferPass.h"
#include "render/sdfshadow/SdfShadowPass.h"
#include "render/shadowmap/ShadowMapPass.h"
#include "render/taa/TaaPass.h"
