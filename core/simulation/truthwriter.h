/***************************************************************************
  truthwriter.h - the ground truth of a simulated survey
  -------------------------------------------------------------------------
  Road lines (centre lines, asphalt edges, markings dash by dash, kerbs) as
  3-D polylines on the terrain, the truth points (objects, manhole lids,
  control targets, road vertices) and, for every image, the exact pixel
  position of each truth point the image sees (in front, in the frame, not
  hidden by terrain or another object).
 ***************************************************************************/
#ifndef GEOSTATION_SIMULATION_TRUTHWRITER_H
#define GEOSTATION_SIMULATION_TRUTHWRITER_H

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/block.h"
#include "simulation/scene.h"

namespace geostation
{

  struct TruthLine
  {
    std::string id;
    std::string kind;    //!< centre, edge, marking or kerb
    std::string road;    //!< road id
    std::string marking; //!< markings: centre, separator or edge_line
    std::vector<Eigen::Vector3d> vertices;
  };

  //! Every road's truth lines, clipped where a road with priority covers them.
  std::vector<TruthLine> roadTruthLines( const Scene &scene );

  struct TruthPoint
  {
    std::string id;
    Eigen::Vector3d point;
    int ownObject = -1; //!< the object this point belongs to (not an occluder of itself)
    const GroundMark *target = nullptr; //!< a control target's mark: how much of its disc each image shows is measured
  };

  //! Objects (not trees or cars), manhole lids, control targets and every road-line vertex ("<line id>:<vertex>").
  std::vector<TruthPoint> truthPoints( const Scene &scene, const std::vector<TruthLine> &lines );

  struct ImageTruthRow
  {
    std::string pointId, imageId;
    double col = 0.0, row = 0.0;
    //! control targets: the white disc's area in the image (pixels), and the fractions of it in view and in sunlight
    std::optional<double> discPx, discInView, discInSun;
  };

  struct TargetCover
  {
    double discPx = 0.0;    //!< area of the whole white disc in the image, pixels
    double inView = 0.0;    //!< fraction of the disc in the frame and not hidden by terrain or an object
    double inSun = 0.0;     //!< fraction of the disc in view and out of every object's shadow
  };

  /**
   * How a control target's white disc (draped on the terrain, as rendered)
   * appears in an image: sampled on a grid of radius / 6 over the disc, each
   * sample weighted by the area its terrain cell covers in the image. A film
   * camera's fiducial marks hide what lies under them.
   */
  TargetCover targetCoverInImage( const Scene &scene, const OrientedImage &image, const GroundMark &target );

  //! The visible truth points of each image of `block` (exact orientation).
  std::vector<ImageTruthRow> imageTruth( const Scene &scene, const Block &block, const std::vector<TruthPoint> &points,
                                         const std::function<void( size_t imagesDone )> &progress = nullptr );

  /**
   * Writes truth.gpkg: layers objects (PointZ: id, kind), roads
   * (LineStringZ: id, kind, road, marking), control (PointZ: id),
   * occluders (PointZ: id, kind, height_m) and the table image_truth
   * (point_id, image_id, col, row, and for control targets disc_px,
   * disc_in_view, disc_in_sun). Throws std::runtime_error.
   */
  void writeTruthGeoPackage( const std::filesystem::path &path, const std::string &crs, const Scene &scene,
                             const std::vector<TruthLine> &lines, const std::vector<ImageTruthRow> &rows );

} // namespace geostation

#endif // GEOSTATION_SIMULATION_TRUTHWRITER_H
