// Moving to the next station in the Multiview with 3 images of 1920 x 1080
// shown (offscreen QGIS canvases, 600 x 500 px each): from the station
// change until every view has drawn its new image. Target: <= 300 ms.
// Baseline in the same run: decoding the same three images whole with GDAL.
#include <cstdio>
#include <filesystem>
#include <unistd.h>

#include <QEventLoop>
#include <QTimer>

#include <gdal.h>
#include <qgsapplication.h>
#include <qgsproject.h>

#include "benchutils.h"
#include "measurementcontroller.h"
#include "measurementstore.h"
#include "multiviewdock.h"
#include "multiviewsession.h"
#include "simulation/surveysimulator.h"

namespace
{
  struct Run
  {
    std::filesystem::path dir;
    std::unique_ptr<GeoStationMultiviewSession> session;
    std::unique_ptr<GeoStationMeasurementStore> store;
    std::unique_ptr<GeoStationMeasurementController> controller;
    std::unique_ptr<GeoStationMultiviewDock> dock;

    Run()
    {
      dir = std::filesystem::temp_directory_path() / ( "geostation-bench-mv-" + std::to_string( ::getpid() ) );
      geostation::SimulationOptions options;
      options.preset = geostation::SurveyPreset::Highway;
      options.outputDir = dir;
      options.stations = 4;
      options.imageWidth = 1920;
      options.imageHeight = 1080;
      options.supersampling = 1;
      geostation::simulateSurvey( options );
      session = std::make_unique<GeoStationMultiviewSession>();
      QString error;
      if ( !session->openBlock( QString::fromStdString( ( dir / "block.geostation.json" ).string() ), &error ) )
        throw std::runtime_error( error.toStdString() );
      store = std::make_unique<GeoStationMeasurementStore>( session.get(), QgsProject::instance() );
      controller = std::make_unique<GeoStationMeasurementController>( session.get(), store.get() );
      dock = std::make_unique<GeoStationMultiviewDock>( session.get(), controller.get(), store.get() );
      dock->resize( 1900, 760 );
      dock->show();
      step(); // the first drawing sets up the canvases
    }
    ~Run()
    {
      dock.reset();
      controller.reset();
      store.reset();
      session.reset();
      std::filesystem::remove_all( dir );
    }

    //! Next station (round the run); milliseconds until all views have drawn it.
    double step()
    {
      QEventLoop loop;
      double shown = -1;
      const QMetaObject::Connection c = QObject::connect( dock.get(), &GeoStationMultiviewDock::stationShown, &loop, [&]( double ms )
      {
        shown = ms;
        loop.quit();
      } );
      QTimer::singleShot( 10000, &loop, &QEventLoop::quit );
      session->setCurrentStation( ( session->currentStation() + 1 ) % session->run().size() );
      if ( shown < 0 )
        loop.exec();
      QObject::disconnect( c );
      return shown;
    }
  };

  //! Destroyed before QGIS exits (its canvases and layers need QGIS).
  std::unique_ptr<Run> gRun;

  Run &run()
  {
    if ( !gRun )
      gRun = std::make_unique<Run>();
    return *gRun;
  }

  void BM_NextStation3x1920x1080( benchmark::State &state )
  {
    Run &r = run();
    for ( auto _ : state )
    {
      const double ms = r.step();
      if ( ms < 0 )
      {
        state.SkipWithError( "the views did not draw within 10 s" );
        break;
      }
      state.SetIterationTime( ms / 1e3 );
    }
    state.SetItemsProcessed( state.iterations() );
  }

  void BM_BaselineDecodeThreeImages( benchmark::State &state )
  {
    Run &r = run();
    std::vector<unsigned char> buffer;
    for ( auto _ : state )
    {
      for ( const QString &id : r.session->viewImages() )
      {
        const geostation::BlockImage &image = r.session->block()->image( id.toStdString() );
        GDALDatasetH ds = GDALOpen( r.session->block()->imageFilePath( image ).string().c_str(), GA_ReadOnly );
        const int w = GDALGetRasterXSize( ds ), h = GDALGetRasterYSize( ds ), bands = GDALGetRasterCount( ds );
        buffer.resize( static_cast<size_t>( w ) * h * bands );
        if ( GDALDatasetRasterIO( ds, GF_Read, 0, 0, w, h, buffer.data(), w, h, GDT_Byte, bands, nullptr, bands, static_cast<GSpacing>( w ) * bands, 1 ) != CE_None )
          state.SkipWithError( "GDAL cannot read the image" );
        GDALClose( ds );
      }
      benchmark::DoNotOptimize( buffer.data() );
    }
    state.SetItemsProcessed( state.iterations() );
  }
}

BENCHMARK( BM_NextStation3x1920x1080 )->UseManualTime()->Unit( benchmark::kMillisecond );
BENCHMARK( BM_BaselineDecodeThreeImages )->Unit( benchmark::kMillisecond );

int main( int argc, char **argv )
{
  QgsApplication app( argc, argv, true );
  QgsApplication::init();
  QgsApplication::initQgis();
  const int result = benchutils::run( argc, argv, []( const benchutils::Rates &rates )
  {
    const double next = benchutils::rate( rates, "BM_NextStation3x1920x1080" ), decode = benchutils::rate( rates, "BM_BaselineDecodeThreeImages" );
    printf( "\nMultiview, 3 views of 1920 x 1080:\n" );
    if ( next > 0 )
      printf( "  next station drawn in all views: %.1f ms (target <= 300: %s)", 1e3 / next, 1e3 / next <= 300.0 ? "met" : "NOT met" );
    if ( next > 0 && decode > 0 )
      printf( "; x%.2f of decoding the three images whole with GDAL (%.1f ms)", next / decode, 1e3 / decode );
    printf( "\n" );
  } );
  gRun.reset();
  QgsApplication::exitQgis();
  return result;
}
