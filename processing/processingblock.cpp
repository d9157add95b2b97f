/***************************************************************************
  processingblock.cpp - block access for Processing algorithms
 ***************************************************************************/
#include "processingblock.h"

#include <algorithm>
#include <functional>
#include <memory>

#include <QFile>
#include <QJsonDocument>
#include <QObject>
#include <QSaveFile>

#include <qgsexception.h>
#include <qgsprocessingfeedback.h>
#include <qgsprocessingparameters.h>
#include <qgsproviderregistry.h>

#include "io/pixelspacegpkg.h"

namespace GeoStationProcessing
{

  geostation::Block loadBlock( const QString &path )
  {
    if ( path.isEmpty() )
      throw QgsProcessingException( QObject::tr( "No block file was given." ) );
    try
    {
      return geostation::Block::load( path.toStdString() );
    }
    catch ( const std::exception &e )
    {
      throw QgsProcessingException( QObject::tr( "Cannot use the block: %1" ).arg( QString::fromStdString( e.what() ) ) );
    }
  }

  const geostation::BlockImage &blockImage( const geostation::Block &block, const QString &imageId )
  {
    try
    {
      return block.image( imageId.toStdString() );
    }
    catch ( const std::exception &e )
    {
      throw QgsProcessingException( QString::fromStdString( e.what() ) );
    }
  }

  const geostation::ExteriorOrientation &requireOriented( const geostation::Block &block, const geostation::BlockImage &image )
  {
    try
    {
      return block.requireExterior( image );
    }
    catch ( const std::exception &e )
    {
      throw QgsProcessingException( QString::fromStdString( e.what() ) );
    }
  }

  geostation::OrientedImage orientedImage( const geostation::Block &block, const geostation::BlockImage &image )
  {
    try
    {
      return block.orientedImage( image );
    }
    catch ( const std::exception &e )
    {
      throw QgsProcessingException( QString::fromStdString( e.what() ) );
    }
  }

  void requireImageFile( const geostation::Block &block, const geostation::BlockImage &image )
  {
    try
    {
      geostation::requireReadableImageFile( block, image );
    }
    catch ( const std::exception &e )
    {
      throw QgsProcessingException( QString::fromStdString( e.what() ) );
    }
  }

  std::shared_ptr<const geostation::RasterReader> openImageFile( const geostation::Block &block, const geostation::BlockImage &image )
  {
    requireImageFile( block, image );
    return std::make_shared<const geostation::RasterReader>( block.imageFilePath( image ).string() );
  }

  bool hasParameterValue( const QVariantMap &parameters, const QString &name )
  {
    const QVariant v = parameters.value( name );
    return v.isValid() && !v.isNull() && !v.toString().trimmed().isEmpty();
  }

  QgsCoordinateReferenceSystem blockCrs( const geostation::Block &block )
  {
    QgsCoordinateReferenceSystem crs;
    if ( !crs.createFromUserInput( QString::fromStdString( block.crs ) ) || !crs.isValid() )
      throw QgsProcessingException( QObject::tr( "QGIS cannot read the block CRS \"%1\"." ).arg( QString::fromStdString( block.crs ) ) );
    return crs;
  }

  std::string blockCrsDefinition( const QgsCoordinateReferenceSystem &crs )
  {
    return ( crs.authid().isEmpty() ? crs.toWkt( QgsCoordinateReferenceSystem::WKT_PREFERRED ) : crs.authid() ).toStdString();
  }

  void removeIfWritten( const QString &path )
  {
    if ( !path.isEmpty() )
      QFile::remove( path );
  }

  namespace
  {
    /**
     * Runs `rewrite` on a written GeoPackage output (path, layer name);
     * other formats are left alone. Its failure says what `purpose` was.
     */
    void rewriteGeoPackageOutput( const QString &destination, const QString &purpose, const std::function<void( const std::string &, const std::string & )> &rewrite )
    {
      const QVariantMap parts = QgsProviderRegistry::instance()->decodeUri( QStringLiteral( "ogr" ), destination );
      const QString path = parts.value( QStringLiteral( "path" ) ).toString();
      if ( !path.endsWith( QLatin1String( ".gpkg" ), Qt::CaseInsensitive ) )
        return;
      try
      {
        rewrite( path.toStdString(), parts.value( QStringLiteral( "layerName" ) ).toString().toStdString() );
      }
      catch ( const std::exception &e )
      {
        throw QgsProcessingException( QObject::tr( "The output %1 was written but %2: %3" ).arg( path, purpose, QString::fromStdString( e.what() ) ) );
      }
    }
  } // namespace

  void markPixelSpaceOutput( const QString &destination )
  {
    rewriteGeoPackageOutput( destination, QObject::tr( "could not be marked as image space" ),
                             []( const std::string &path, const std::string &layer ) { geostation::markGeoPackageLayerAsPixelSpace( path, layer ); } );
  }

  void storeMissingGeometriesAsNull( const QString &destination )
  {
    rewriteGeoPackageOutput( destination, QObject::tr( "its unresolved features could not be stored without geometry" ),
                             []( const std::string &path, const std::string &layer ) { geostation::nullEmptyGeoPackageGeometries( path, layer ); } );
  }

  QgsProcessingParameterFile *blockParameter()
  {
    return new QgsProcessingParameterFile( QStringLiteral( "BLOCK" ), QObject::tr( "GeoStation block" ), QgsProcessingParameterFile::File,
                                           QString(), QVariant(), false, QObject::tr( "GeoStation block (*.geostation.json *.json)" ) );
  }

  QgsProcessingParameterFileDestination *htmlReportParameter()
  {
    return new QgsProcessingParameterFileDestination( QStringLiteral( "REPORT_HTML" ), QObject::tr( "Readable report (HTML)" ), QObject::tr( "HTML files (*.html)" ), QVariant(), true, false );
  }

  QByteArray jsonReport( const QJsonObject &report )
  {
    return QJsonDocument( report ).toJson( QJsonDocument::Indented );
  }

  namespace
  {
    //! The reports asked for, open and written but not yet committed (a QSaveFile destroyed uncommitted leaves nothing).
    std::vector<std::unique_ptr<QSaveFile>> stageReports( const QVector<ReportFile> &reports )
    {
      std::vector<std::unique_ptr<QSaveFile>> staged;
      for ( const ReportFile &r : reports )
      {
        if ( r.path.isEmpty() )
          continue;
        auto file = std::make_unique<QSaveFile>( r.path );
        if ( !file->open( QIODevice::WriteOnly ) || file->write( r.contents ) != r.contents.size() )
          throw QgsProcessingException( QObject::tr( "Cannot write the report %1." ).arg( r.path ) );
        staged.push_back( std::move( file ) );
      }
      return staged;
    }

    void commitReports( std::vector<std::unique_ptr<QSaveFile>> &staged )
    {
      for ( std::unique_ptr<QSaveFile> &f : staged )
        if ( !f->commit() )
          throw QgsProcessingException( QObject::tr( "Cannot write the report %1." ).arg( f->fileName() ) );
    }
  } // namespace

  void writeBlockAndReports( const geostation::Block &block, const QString &blockPath, const QVector<ReportFile> &reports )
  {
    std::vector<std::unique_ptr<QSaveFile>> staged = stageReports( reports );
    try
    {
      block.save( blockPath.toStdString() );
    }
    catch ( const std::exception &e )
    {
      throw QgsProcessingException( QString::fromStdString( e.what() ) );
    }
    commitReports( staged );
  }

  void writeReports( const QVector<ReportFile> &reports )
  {
    std::vector<std::unique_ptr<QSaveFile>> staged = stageReports( reports );
    commitReports( staged );
  }

  void writeReport( const QJsonObject &report, const QString &reportPath )
  {
    writeReports( { { reportPath, jsonReport( report ) } } );
  }

  LoadedDem loadDem( const QString &path, const geostation::Block &block, const geostation::DemOptions &options )
  {
    LoadedDem out;
    try
    {
      out.dem = std::make_unique<geostation::Dem>( path.toStdString(), options );
      out.blockToDem = std::make_unique<geostation::CrsTransform>( block.crs, out.dem->crsWkt() );
    }
    catch ( const std::exception &e )
    {
      throw QgsProcessingException( QString::fromStdString( e.what() ) );
    }
    return out;
  }

  geostation::Progress progressOf( QgsProcessingFeedback *feedback )
  {
    if ( !feedback )
      return geostation::Progress();
    // the text beside the bar names the stage: a message is shown when its words before the first one holding a
    // digit change ("station S0001", "station S0002", ... once; qgis_process prints every text it is given)
    auto shown = std::make_shared<QString>();
    return geostation::Progress( [feedback, shown]( double fraction, const std::string &message ) {
      feedback->setProgress( 100.0 * fraction );
      const QString text = QString::fromStdString( message );
      QStringList stage;
      for ( const QString &word : text.split( ' ', Qt::SkipEmptyParts ) )
      {
        if ( std::any_of( word.begin(), word.end(), []( QChar c ) { return c.isDigit(); } ) )
          break;
        stage << word;
      }
      if ( !text.isEmpty() && stage.join( ' ' ) != *shown )
      {
        *shown = stage.join( ' ' );
        feedback->setProgressText( text );
      }
    }, [feedback] { return feedback->isCanceled(); } );
  }
}
