// Rendering speed of the survey simulator, one core: megapixels per second
// for one image of each preset, against rendering the same image with every
// pixel supersampled n x n (n = 3, the default) (the baseline the adaptive anti-aliasing avoids).
// Target: at least 1 Mpx/s on one core.
#include <cstdio>
#include <memory>
#include <tuple>

#include "benchutils.h"
#include "simulation/renderer.h"
#include "simulation/surveyrig.h"
#include "simulation/surveysimulator.h"

using namespace geostation;

namespace
{
  struct PresetScene
  {
    BuiltScene built;
    Block truth, noisy;
  };

  const PresetScene &presetScene( SurveyPreset preset )
  {
    static std::map<SurveyPreset, std::unique_ptr<PresetScene>> cache;
    std::unique_ptr<PresetScene> &entry = cache[preset];
    if ( !entry )
    {
      SimulationOptions options;
      options.preset = preset;
      options.seed = 3;
      options.stations = preset == SurveyPreset::Highway ? 12 : 0;
      options.outputDir = "unused";
      const RigSettings settings = rigSettings( options );
      const SceneRequest request = sceneRequest( options, settings );
      entry = std::make_unique<PresetScene>();
      entry->built = buildScene( request );
      buildRig( options, settings, entry->built, entry->truth, entry->noisy );
    }
    return *entry;
  }

  void render( benchmark::State &state, SurveyPreset preset, bool adaptive )
  {
    const PresetScene &s = presetScene( preset );
    const BlockImage &image = s.truth.images[s.truth.images.size() / 2];
    const Camera &camera = s.truth.cameraOf( image );
    const CameraRays rays( camera );
    const OrientedImage oriented( camera, *image.exterior );
    RenderOptions options;
    options.threads = 1;
    options.adaptive = adaptive;
    RenderSummary summary;
    for ( auto _ : state )
      benchmark::DoNotOptimize( renderImage( *s.built.scene, oriented, &rays, options, &summary ).data );
    state.SetItemsProcessed( state.iterations() * static_cast<long>( camera.width ) * camera.height );
    state.SetLabel( std::to_string( camera.width ) + "x" + std::to_string( camera.height ) );
    state.counters["rays_per_px"] = static_cast<double>( summary.rays ) / std::max( 1L, summary.pixels );
  }

  void BM_HighwayUniform( benchmark::State &state ) { render( state, SurveyPreset::Highway, false ); }
  void BM_HighwayAdaptive( benchmark::State &state ) { render( state, SurveyPreset::Highway, true ); }
  void BM_AerialAdaptive( benchmark::State &state ) { render( state, SurveyPreset::AerialStereo, true ); }
  void BM_ObliqueAdaptive( benchmark::State &state ) { render( state, SurveyPreset::ObliquePhoto, true ); }
}

BENCHMARK( BM_HighwayUniform )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_HighwayAdaptive )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_AerialAdaptive )->Unit( benchmark::kMillisecond );
BENCHMARK( BM_ObliqueAdaptive )->Unit( benchmark::kMillisecond );

int main( int argc, char **argv )
{
  return benchutils::run( argc, argv, []( const benchutils::Rates &rates )
  {
    const double baseline = benchutils::rate( rates, "BM_HighwayUniform" );
    printf( "\nRendered pixels per second on one core (target 1 Mpx/s), against supersampling every pixel of the highway image in this run:\n" );
    for ( const char *name : { "BM_HighwayAdaptive", "BM_AerialAdaptive", "BM_ObliqueAdaptive" } )
    {
      const double a = benchutils::rate( rates, name );
      if ( a > 0.0 && baseline > 0.0 )
        printf( "  %-20s %6.2f Mpx/s  x%.1f of the baseline; target 1 Mpx/s: %s\n", name, a / 1e6, a / baseline, a >= 1e6 ? "met" : "NOT met" );
    }
  } );
}
