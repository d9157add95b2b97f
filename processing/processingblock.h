/***************************************************************************
  processingblock.h - block access for Processing algorithms
  -------------------------------------------------------------------------
  Turns core's exceptions into QgsProcessingException with one clear
  sentence, so every algorithm fails the same way on bad input.
 ***************************************************************************/
#ifndef PROCESSINGBLOCK_H
#define PROCESSINGBLOCK_H

#include <QJsonObject>
#include <QVariantMap>
#include <QVector>
#include <QString>

#include <qgscoordinatereferencesystem.h>

#include <memory>
#include <string>

#include "dem/dem.h"
#include "geometry/crs.h"
#include "io/block.h"
#include "io/rasterfile.h"
#include "progress/progress.h"

class QgsProcessingFeedback;
class QgsProcessingParameterFile;
class QgsProcessingParameterFileDestination;

namespace GeoStationProcessing
{
  //! Loads a block file; throws QgsProcessingException on any problem.
  geostation::Block loadBlock( const QString &path );

  //! An image of the block by id; throws QgsProcessingException naming the ids.
  const geostation::BlockImage &blockImage( const geostation::Block &block, const QString &imageId );

  //! The image's exterior orientation; throws QgsProcessingException if not oriented.
  const geostation::ExteriorOrientation &requireOriented( const geostation::Block &block, const geostation::BlockImage &image );

  /**
   * The oriented image, with the scan affine of its inner orientation when it
   * has one (scanned film); throws QgsProcessingException like requireOriented().
   */
  geostation::OrientedImage orientedImage( const geostation::Block &block, const geostation::BlockImage &image );

  //! Checks the image file exists, decodes and has its camera's size.
  void requireImageFile( const geostation::Block &block, const geostation::BlockImage &image );
  //! The image's file opened for reading in windows, after requireImageFile().
  std::shared_ptr<const geostation::RasterReader> openImageFile( const geostation::Block &block, const geostation::BlockImage &image );

  //! Whether an optional parameter was given (not missing, NULL or blank).
  bool hasParameterValue( const QVariantMap &parameters, const QString &name );

  //! The block CRS as a QGIS CRS; throws QgsProcessingException if QGIS cannot read it.
  QgsCoordinateReferenceSystem blockCrs( const geostation::Block &block );
  //! A QGIS CRS as a block's CRS: the authority id when QGIS has one, else WKT.
  std::string blockCrsDefinition( const QgsCoordinateReferenceSystem &crs );

  /**
   * Marks a written image-space output as Cartesian without CRS where the
   * format needs it (GeoPackage: srs_id -1). Other outputs are left alone.
   */
  void markPixelSpaceOutput( const QString &destination );

  /**
   * A written vector output with its unresolved features' geometries NULL:
   * QGIS writes a feature without geometry as an empty one, which a
   * GeoPackage stores, for a point, as NaN coordinates (pixelspacegpkg.h).
   * Other formats are left alone (a Shapefile writes a null shape).
   */
  void storeMissingGeometriesAsNull( const QString &destination );

  //! The BLOCK parameter every algorithm takes.
  QgsProcessingParameterFile *blockParameter();

  //! REPORT_HTML, the optional report a person reads (htmlreport.h), shown in the Results Viewer.
  QgsProcessingParameterFileDestination *htmlReportParameter();

  //! A report file to write: its path (empty: not asked for) and its contents.
  struct ReportFile
  {
    QString path;
    QByteArray contents;
  };

  //! A JSON report as written (indented UTF-8).
  QByteArray jsonReport( const QJsonObject &report );

  /**
   * Writes a block and its reports, all or none: the reports are staged and
   * committed only once the block has been saved (atomically). Reports with
   * an empty path (the optional reports not asked for) are left out.
   */
  void writeBlockAndReports( const geostation::Block &block, const QString &blockPath, const QVector<ReportFile> &reports );
  //! Writes reports, all or none (staged, then renamed); throws QgsProcessingException with one sentence.
  void writeReports( const QVector<ReportFile> &reports );
  //! Writes a JSON report atomically (a temporary file renamed); throws QgsProcessingException with one sentence.
  void writeReport( const QJsonObject &report, const QString &reportPath );
  //! Removes an output a failed run had begun to write (nothing for an empty path).
  void removeIfWritten( const QString &path );
  //! A DEM and the transform from the block CRS to its CRS.
  struct LoadedDem
  {
    std::unique_ptr<geostation::Dem> dem;
    std::unique_ptr<geostation::CrsTransform> blockToDem;
  };

  /**
   * The algorithm's feedback as core's Progress: a fraction sets the
   * progress bar (0-1 as 0-100 %), a message the text beside it, and
   * Cancel is the stop. Use part() for a share of the bar.
   */
  geostation::Progress progressOf( QgsProcessingFeedback *feedback );

  //! Opens a DEM file for a block; throws QgsProcessingException with one sentence.
  LoadedDem loadDem( const QString &path, const geostation::Block &block, const geostation::DemOptions &options = geostation::DemOptions() );
}

#endif // PROCESSINGBLOCK_H
