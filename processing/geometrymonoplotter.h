/***************************************************************************
  geometrymonoplotter.h - an image-space geometry onto the DEM, for monoplot
 ***************************************************************************/
#ifndef GEOMETRYMONOPLOTTER_H
#define GEOMETRYMONOPLOTTER_H

#include <memory>
#include <optional>

#include <QString>
#include <qgsabstractgeometry.h>
#include <qgslinestring.h>
#include <qgspoint.h>

#include "dem/monoplotter.h"

namespace GeoStationProcessing
{
  /**
   * Monoplots one image-space geometry (x = col, y = -row) onto the DEM:
   * points ray by ray, lines and rings densified to densifyPx so they drape
   * over the terrain. geometry() fills `worst` with the largest vertex sigmas
   * and counts the vertices; when the geometry cannot be monoplotted it
   * returns nullptr with `problem` (one sentence) and `status` (outside_image,
   * misses_dem, below_dem, dem_hole). A line (not a ring) that meets a hole
   * or the horizon part-way keeps its longest resolved part: the geometry is
   * returned with `cutVertices` > 0 and `problem` and `status` saying why.
   */
  struct GeometryMonoplotter
  {
    const geostation::Monoplotter &monoplotter;
    double densifyPx;
    int width, height;                         //!< the image frame (pixels)
    Eigen::Vector3d worst = Eigen::Vector3d::Zero(); //!< largest vertex sigmas (m)
    int vertices = 0;
    int bridged = 0;                           //!< vertices on bridged DEM cells
    int cutVertices = 0;                       //!< densified vertices of lines cut away (not resolved, or off the kept part)
    QString problem {};
    QString status {};

    //! Ready for the next feature: counts cleared, `problem` and `status` preset to `why` for a geometry type that cannot be monoplotted.
    void reset( const QString &why, const QString &statusName );
    void fail( const QString &why, const QString &statusName );
    bool inFrame( const QgsPoint &p ) const;
    std::optional<QgsPoint> point( const Eigen::Vector2d &pixel );
    std::unique_ptr<QgsLineString> line( const QgsLineString &in, bool closed );
    //! The geometry on the DEM (with Z), or nullptr.
    std::unique_ptr<QgsAbstractGeometry> geometry( const QgsAbstractGeometry *g );
  };

} // namespace GeoStationProcessing

#endif // GEOMETRYMONOPLOTTER_H
