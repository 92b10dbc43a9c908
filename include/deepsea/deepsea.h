#pragma once
/// \file The front door: one include for a program that bakes, loads and renders with deepsea
/// (link deepsea::deepsea). A frame is rendered by a Renderer made from an asset:
///
///     const deepsea::Asset asset = deepsea::load_asset("rig__water.vdb");
///     deepsea::Renderer renderer(asset);
///     deepsea::Layers layers;
///     renderer.render(layers, color, depth);  // views of the caller's memory (frame_view.h)
///
/// or renderer.render(layers, frame) for a deepsea::Frame read from files (io/image_io.h).
/// Setups (camera, rig, water) come from YAML (io/config.h); images from files (io/image_io.h).
/// A CameraStage (camera/camera_stage.h) records the radiance as a real camera would; its
/// auto-exposure controller (camera/auto_exposure.h) sets each frame's exposure in a sequence.
/// A robot middleware's node renders a stream of image messages with live/ (docs/ros.md).

#include "deepsea/asset/asset_file.h"
#include "deepsea/bake/bake.h"
#include "deepsea/batch/layer_files.h"
#include "deepsea/camera/auto_exposure.h"
#include "deepsea/camera/camera_stage.h"
#include "deepsea/core/error.h"
#include "deepsea/core/frame.h"
#include "deepsea/core/image.h"
#include "deepsea/io/config.h"
#include "deepsea/io/image_io.h"
#include "deepsea/live/image_message.h"
#include "deepsea/live/latest_slot.h"
#include "deepsea/live/live_renderer.h"
#include "deepsea/live/stamp_pairer.h"
#include "deepsea/runtime/exposure.h"
#include "deepsea/runtime/renderer.h"
#include "deepsea/version.h"
