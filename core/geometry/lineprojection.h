/***************************************************************************
  lineprojection.h - map lines and rings into an oriented image
  -------------------------------------------------------------------------
  What drawing a map feature in a photo needs besides collinearity: a line
  is densified so its straight map segments follow their curves in the
  photo; a line that leaves the part of space the image can show (behind
  the camera, or far outside the lens field) is cut where it leaves it, and
  a ring is clipped to that space in 3-D, so nothing is ever drawn through
  the region that cannot be shown. The projection itself is a callback, so
  the terrain's occlusion (monoplotter) can take part.
 ***************************************************************************/
#ifndef GEOSTATION_GEOMETRY_LINEPROJECTION_H
#define GEOSTATION_GEOMETRY_LINEPROJECTION_H

#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "geometry/projection.h"

namespace geostation
{

  //! A ground point's pixel, or nothing where it cannot be projected (behind the camera, outside the lens field).
  using GroundToPixel = std::function<std::optional<Eigen::Vector2d>( const Eigen::Vector3d & )>;

  //! A class of a projectable ground point (e.g. 1: hidden by the terrain, 0: seen), where runs are split.
  using GroundClass = std::function<int( const Eigen::Vector3d & )>;

  struct ProjectedPolylineParts
  {
    std::vector<std::vector<Eigen::Vector2d>> parts; //!< runs of at least two pixels, in the polyline's order
    std::vector<int> classes;                         //!< each part's class (0 without a classifier)
    int longest = -1;                                 //!< index of the longest part (in pixels), -1 when none
  };

  /**
   * An open map polyline (block CRS, densified) projected by `project` and
   * cut where it leaves the projectable field: the boundary on each ground
   * segment that crosses it is found by bisection (40 halvings) and ends the
   * part, so no piece of line is drawn through the region that cannot be
   * shown. `classify` (optional): a part also ends where the class of its
   * points changes, the last point of one part the first of the next (the
   * drawn line has no gap).
   */
  ProjectedPolylineParts projectPolylineCut( const std::vector<Eigen::Vector3d> &dense, const GroundToPixel &project, const GroundClass &classify = nullptr );

  //! A ground point seen from the image: its projection, and whether the terrain leaves it visible.
  struct GroundPointView
  {
    GroundProjection projection;
    bool visible = true;
  };
  using GroundPointViewer = std::function<GroundPointView( const Eigen::Vector3d & )>;

  struct GroundLineOptions
  {
    double densifyPx = 2.0; //!< longest projected piece, pixels
    //! Heights of inserted points (e.g. from a DEM); linear interpolation when empty or when it gives none.
    std::function<std::optional<double>( const Eigen::Vector3d & )> heightAt;
    bool closed = false;    //!< a ring: clipped in 3-D to the image's field instead of cut
    /**
     * Parts also split where the terrain starts or stops hiding the line (a
     * point in the frame that the viewer says is not visible is hidden); a
     * ring is then cut as an open line, not clipped.
     */
    bool splitHidden = false;
  };

  struct ProjectedGroundLine
  {
    /**
     * Pixels (col, row). parts[0] is the feature: the whole line, the
     * clipped ring (closed: first == last) or, for a line cut into several
     * runs, the longest; the other runs follow in the line's order. Empty
     * when nothing of the line can be shown.
     */
    std::vector<std::vector<Eigen::Vector2d>> parts;
    std::vector<bool> hidden; //!< per part: behind the terrain (GroundLineOptions::splitHidden; else all false)
    bool clipped = false;     //!< cut or clipped at the edge of the projectable space (and something of it shown)
    bool behind = false;      //!< some vertex lay behind the camera
    bool allInFrame = true;   //!< every projected vertex on the frame
    bool allVisible = true;   //!< no vertex hidden by the terrain (as the viewer says)
    double minDepthM = std::numeric_limits<double>::infinity(); //!< of what is drawn (a clipped ring: of the clipped ring)
  };

  /**
   * A map line or ring (block CRS, metres, with heights) in the image.
   * Throws std::invalid_argument if options.densifyPx <= 0.
   */
  ProjectedGroundLine projectGroundLine( const OrientedImage &image, const std::vector<Eigen::Vector3d> &vertices, const GroundPointViewer &view,
                                         const GroundLineOptions &options );

  //! What projecting one map feature found out, over all its points and lines.
  struct FeatureProjectionTally
  {
    bool behind = false;     //!< some vertex lies behind the camera
    bool clipped = false;    //!< a line was cut where it leaves the projectable field
    bool allInFrame = true;
    bool allVisible = true;
    double minDepthM = std::numeric_limits<double>::infinity();

    //! Adds a projected point.
    void add( const GroundPointView &view );
    //! Adds a projected line; `partsDropped`: runs other than the first are not kept (they count as behind).
    void add( const ProjectedGroundLine &line, bool partsDropped );
  };

} // namespace geostation

#endif // GEOSTATION_GEOMETRY_LINEPROJECTION_H
