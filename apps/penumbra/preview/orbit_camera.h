// The preview page's camera moves: orbit about the look-at point, zoom
// towards it, pan across the view; and a camera written as the command line's
// options, so that a view found in the browser renders again from the shell.
#pragma once

#include <string>

#include <penumbra/penumbra.hpp>

namespace penumbra::preview {

/// Turns the eye about the look-at point, keeping its distance and `up`:
/// `yawDegrees` about the up vector (a turntable), `pitchDegrees` about the
/// view's horizontal axis (positive raises the eye), stopping 1 degree short
/// of looking along up or against it, where the view would lose its horizon.
pnb::Camera orbit(const pnb::Camera& camera, double yawDegrees, double pitchDegrees);

/// Moves the eye along the line of sight to `factor` times its distance from
/// the look-at point (factor < 1 comes closer); an explicit focus distance
/// scales with it, so the same point stays in focus.
pnb::Camera zoom(const pnb::Camera& camera, double factor);

/// Slides eye and look-at together across the view by `right` and `up`
/// times the height the view spans at the look-at point.
pnb::Camera pan(const pnb::Camera& camera, double right, double up);

/// "--eye=x,y,z --look-at=x,y,z --up=x,y,z --fov=f", plus "--aperture=r
/// --focus-distance=d" for a thin lens: every number written with enough
/// digits to read back as the same float, so the options give the same image.
std::string cameraOptions(const pnb::Camera& camera);

}  // namespace penumbra::preview
