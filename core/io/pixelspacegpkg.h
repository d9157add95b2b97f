/***************************************************************************
  pixelspacegpkg.h - GeoPackage layers in image (pixel) space
  -------------------------------------------------------------------------
  An image-space layer (x = col, y = -row, docs/conventions.md §1) has no CRS. GDAL
  3.6 writes such a layer with srs_id 0, "Undefined geographic SRS", which
  QGIS then reads as a geographic CRS. The GeoPackage way to say "Cartesian,
  no CRS" is srs_id -1; this rewrites a layer to it.

  QGIS 3.22 writes a feature without geometry into a GeoPackage layer of a
  geometry type as that type's empty geometry, and an empty point is stored
  as the coordinates NaN, NaN: a feature that could not be resolved would
  carry NaN coordinates. nullEmptyGeoPackageGeometries() stores NULL for
  each empty geometry instead.
 ***************************************************************************/
#ifndef GEOSTATION_IO_PIXELSPACEGPKG_H
#define GEOSTATION_IO_PIXELSPACEGPKG_H

#include <filesystem>
#include <string>

namespace geostation
{

  /**
   * Sets srs_id = -1 ("Undefined Cartesian SRS") on a GeoPackage layer: in
   * gpkg_contents, gpkg_geometry_columns and every geometry's header. An empty
   * layerName means the file's only layer. Throws std::runtime_error.
   */
  void markGeoPackageLayerAsPixelSpace( const std::filesystem::path &file, const std::string &layerName = std::string() );

  /**
   * Stores NULL for every empty geometry of a GeoPackage layer (an empty
   * layerName: the file's only layer); returns how many. Throws
   * std::runtime_error.
   */
  int nullEmptyGeoPackageGeometries( const std::filesystem::path &file, const std::string &layerName = std::string() );

} // namespace geostation

#endif // GEOSTATION_IO_PIXELSPACEGPKG_H
