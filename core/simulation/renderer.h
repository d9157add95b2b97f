/***************************************************************************
  renderer.h - image formation: ray casting through the camera model
  -------------------------------------------------------------------------
  Every sample's ray comes from Camera::rayInCameraFromPixel() and the
  exterior orientation (docs/conventions.md §1-3), so the rendered image and the
  camera model agree by construction: a ground point projects with
  projectGroundToPixel() to where the renderer drew it.

  Anti-aliasing is adaptive: one ray through each pixel centre, then every
  pixel whose 4-neighbourhood (3 x 3 next to control targets) shows
  different surfaces (materials,
  objects, shadow edges, the horizon) is re-rendered as the mean of
  n x n stratified samples over its area (4n x 4n on the edges of control
  targets, which are measured to hundredths of a pixel).
 ***************************************************************************/
#ifndef GEOSTATION_SIMULATION_RENDERER_H
#define GEOSTATION_SIMULATION_RENDERER_H

#include <vector>

#include <Eigen/Core>
#include <opencv2/core.hpp>

#include "geometry/projection.h"
#include "simulation/scene.h"

namespace geostation
{

  /**
   * Camera-frame rays on a lattice of pixel corners (every pixel, or every
   * second one for images over 4 Mpx), from Camera::rayInCameraFromPixel(),
   * shared by all images of a camera. Rays between the nodes are bilinear in
   * the lattice: the lens models are smooth enough that this stays within
   * 1e-3 px of the exact ray (pinned by a test), and it spares the iterative
   * inversion of the distortion for every sample.
   */
  class CameraRays
  {
    public:
      explicit CameraRays( const Camera &camera );

      //! The (unnormalised) ray through a pixel position; false outside the lens field.
      bool rayAt( double col, double row, Eigen::Vector3d &rayInCamera ) const;

      int latticeStep() const { return mStep; }

    private:
      int mStep = 1;
      int mMargin = 0; //!< lattice nodes reach this many pixels beyond the frame
      int mNodesX = 0, mNodesY = 0;
      std::vector<Eigen::Vector3f> mRays;
      std::vector<char> mValid;
  };

  struct RenderOptions
  {
    int supersampling = 3; //!< n: n x n samples in pixels on an edge (1 = none); ground marks get 4n x 4n
    int threads = 1;       //!< worker threads for this image
    bool adaptive = true;  //!< false: supersample every pixel (the slow reference)
  };

  struct RenderSummary
  {
    long rays = 0;
    long supersampledPixels = 0;
    long skyPixels = 0;
    long pixels = 0;
  };

  /**
   * Renders `image` of `scene` as linear RGB (CV_32FC3, 0..1 for a white
   * surface in full sun); a scan affine (scanned film) is honoured. `rays` must belong to the image's camera (may be
   * null: computed here).
   */
  cv::Mat renderImage( const Scene &scene, const OrientedImage &image, const CameraRays *rays, const RenderOptions &options,
                       RenderSummary *summary = nullptr );

} // namespace geostation

#endif // GEOSTATION_SIMULATION_RENDERER_H
