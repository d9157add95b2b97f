/***************************************************************************
  crs.h - checks on a block's coordinate reference system (CONVENTIONS §4)
 ***************************************************************************/
#ifndef GEOSTATION_GEOMETRY_CRS_H
#define GEOSTATION_GEOMETRY_CRS_H

#include <string>

namespace geostation
{

  struct CrsDescription
  {
    std::string name;     //!< PROJ's name of the CRS, e.g. "WGS 84 / UTM zone 17N"
    std::string kind;     //!< "projected", "engineering", "geographic", "geocentric", ...
    std::string unitName; //!< unit of the first horizontal axis, e.g. "metre"
    double unitToMetre = 0.0;
  };

  /**
   * Describes a CRS given as anything PROJ reads (EPSG:xxxx, WKT, PROJ string).
   * For a compound CRS the horizontal part is described.
   * Throws std::invalid_argument when PROJ does not recognise it.
   */
  CrsDescription describeCrs( const std::string &definition );

  /**
   * Throws std::invalid_argument with a sentence a surveyor understands unless
   * the CRS is projected (or a local engineering CRS) with axes in metres.
   */
  void requireProjectedMetricCrs( const std::string &definition );

} // namespace geostation

#endif // GEOSTATION_GEOMETRY_CRS_H
