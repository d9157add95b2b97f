/***************************************************************************
  imagespace.h - pixels in QGIS's image space, and back
  -------------------------------------------------------------------------
  docs/conventions.md §1: core measures pixels as (col, row), row down; a
  layer of a photo in QGIS has no CRS and uses x = col, y = -row, so the
  photo lies right side up in a canvas whose y runs up. The one place the
  flip is written.
 ***************************************************************************/
#ifndef GEOSTATION_GEOMETRY_IMAGESPACE_H
#define GEOSTATION_GEOMETRY_IMAGESPACE_H

#include <Eigen/Core>

namespace geostation
{

  //! A pixel (col, row) in image space: (col, -row).
  inline Eigen::Vector2d imageSpaceOfPixel( const Eigen::Vector2d &pixel ) { return Eigen::Vector2d( pixel.x(), -pixel.y() ); }

  //! An image-space point (x, y) as a pixel: (x, -y).
  inline Eigen::Vector2d pixelOfImageSpace( const Eigen::Vector2d &xy ) { return Eigen::Vector2d( xy.x(), -xy.y() ); }

} // namespace geostation

#endif // GEOSTATION_GEOMETRY_IMAGESPACE_H
