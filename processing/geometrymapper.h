/***************************************************************************
  geometrymapper.h - rebuild a QGIS geometry vertex by vertex
  -------------------------------------------------------------------------
  Walks points, curves, polygon rings and collections, mapping each point
  and each line (densified as the caller likes) to a new geometry of the same
  structure. Used to carry features between map and image space.
 ***************************************************************************/
#ifndef GEOMETRYMAPPER_H
#define GEOMETRYMAPPER_H

#include <functional>
#include <memory>
#include <optional>

#include <qgsabstractgeometry.h>
#include <qgslinestring.h>
#include <qgspoint.h>
#include <qgswkbtypes.h>

namespace GeoStationProcessing
{
  struct GeometryMapper
  {
    //! A point mapped, or nothing when it cannot be.
    std::function<std::optional<QgsPoint>( const QgsPoint & )> point;
    //! A line (a polygon ring when `closed`) mapped, or nullptr when it cannot be.
    std::function<std::unique_ptr<QgsLineString>( const QgsLineString &, bool closed )> line;
    /**
     * Optional, for the lines of a collection (multi-line): all the pieces a
     * line maps to (it may fall apart); empty when none can be mapped.
     */
    std::function<std::vector<std::unique_ptr<QgsLineString>>( const QgsLineString & )> lineParts;
    //! The type of an output collection given the input's.
    std::function<QgsWkbTypes::Type( QgsWkbTypes::Type )> collectionType;
  };

  /**
   * The geometry rebuilt through `mapper`; nullptr when any part cannot be
   * mapped. Throws QgsProcessingException for unsupported geometry types.
   */
  std::unique_ptr<QgsAbstractGeometry> mapGeometry( const QgsAbstractGeometry *geometry, const GeometryMapper &mapper );
}

#endif // GEOMETRYMAPPER_H
