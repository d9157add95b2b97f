/***************************************************************************
  metashapeimport.h - Metashape's camera XML as a GeoStation block
  -------------------------------------------------------------------------
  The file Metashape writes with File > Export > Export Cameras (Agisoft
  XML): a <chunk> with <sensors> (calibrations), <cameras> (each a 4 x 4
  <transform> from the camera to the chunk's internal frame) and, when the
  chunk is referenced, the chunk's <transform> (<rotation>, <translation>,
  <scale>: internal to geocentric coordinates) and its <reference> CRS.

  Frame sensors convert exactly, following Metashape's camera model
  (manual, appendix "Camera models"; camera x right, y down, z forward):
      x' = x (1 + K1 r^2 + K2 r^4 + K3 r^6) + P1 (r^2 + 2 x^2) + 2 P2 x y
      y' = y (1 + K1 r^2 + K2 r^4 + K3 r^6) + P2 (r^2 + 2 y^2) + 2 P1 x y
      u = w / 2 + cx + x' (f + B1) + y' B2,   v = h / 2 + cy + y' f
  with the centre of the first pixel at (0.5, 0.5), as in GeoStation. That
  is the "opencv" model with fx = f + B1, fy = f, k1-k3 = K1-K3, and p1 =
  P2, p2 = P1 (Metashape numbers the tangential terms the other way round).
  K4, P3, P4 or the skew B2 other than 0, and sensors other than frame
  (fisheye, spherical, cylindrical), are refused by name with their images.

  A referenced chunk's cameras are brought from geocentric coordinates
  (EPSG:4978) into the block CRS with PROJ: centres transformed, attitudes
  rotated by the local rotation of the CRS (east-north-up and meridian
  convergence), taken from PROJ's derivatives at each centre. An
  unreferenced chunk keeps its internal frame (georeference it with
  georeferenceImport()).

  Markers with reference coordinates become control points (check points
  where the reference is not enabled), brought from the chunk's reference
  CRS into the block CRS; their pinned projections in the imported cameras
  become their observations (Metashape's own estimates, not pinned, are
  left out).
 ***************************************************************************/
#ifndef GEOSTATION_IO_METASHAPEIMPORT_H
#define GEOSTATION_IO_METASHAPEIMPORT_H

#include <filesystem>
#include <string>

#include "io/blockimport.h"

namespace geostation
{

  struct MetashapeImportOptions
  {
    std::string crs;                     //!< the block CRS (projected or local engineering, metres); required
    std::filesystem::path imageFolder;   //!< where the camera labels resolve; empty: the XML file's folder
    bool requireImageFiles = true;       //!< every image must exist, decode and have its camera's size
  };

  //! True when the file is XML with a <chunk> holding <sensors> or <cameras>.
  bool isMetashapeCameras( const std::filesystem::path &file );

  /**
   * Reads Metashape's camera XML. Images are found by label in the image
   * folder (the label itself, or the label with .jpg, .jpeg, .tif, .tiff or
   * .png in either case). Throws std::invalid_argument with one sentence;
   * nothing is written.
   */
  BlockImportSummary importMetashapeCameras( const std::filesystem::path &xmlFile, const MetashapeImportOptions &options );

} // namespace geostation

#endif // GEOSTATION_IO_METASHAPEIMPORT_H
