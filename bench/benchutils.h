// Shared by the benchmark programs: run Google Benchmark, collect each
// result's items per second, and print a summary of ratios against the
// baselines measured in the same run.
#ifndef GEOSTATION_BENCHUTILS_H
#define GEOSTATION_BENCHUTILS_H

#include <cstdlib>
#include <fstream>
#include <functional>
#include <map>
#include <string>

#include <benchmark/benchmark.h>

namespace benchutils
{
  using Rates = std::map<std::string, double>; //!< benchmark name -> items per second

  class RateReporter : public benchmark::ConsoleReporter
  {
    public:
      explicit RateReporter( std::function<void( const Rates & )> summary ) : mSummary( std::move( summary ) ) {}

      void ReportRuns( const std::vector<Run> &runs ) override
      {
        ConsoleReporter::ReportRuns( runs );
        for ( const Run &run : runs )
          if ( run.counters.count( "items_per_second" ) )
            mRates[run.benchmark_name() + ( run.report_label.empty() ? std::string() : " (" + run.report_label + ")" )] = run.counters.at( "items_per_second" ).value;
      }

      void Finalize() override
      {
        ConsoleReporter::Finalize();
        mSummary( mRates );
      }

    private:
      std::function<void( const Rates & )> mSummary;
      Rates mRates;
  };

  //! main(): runs the registered benchmarks, then prints `summary`.
  inline int run( int argc, char **argv, std::function<void( const Rates & )> summary )
  {
    benchmark::Initialize( &argc, argv );
    RateReporter reporter( std::move( summary ) );
    benchmark::RunSpecifiedBenchmarks( &reporter );
    benchmark::Shutdown();
    return 0;
  }

  //! The rate of the first result whose name starts with `prefix`, or 0.
  //! A field of /proc/self/status in kB ("VmRSS:" resident now, "VmHWM:" its peak); -1 where there is none (not Linux).
  inline long statusKb( const std::string &field )
  {
    std::ifstream status( "/proc/self/status" );
    std::string line;
    while ( std::getline( status, line ) )
      if ( line.rfind( field, 0 ) == 0 )
        return std::atol( line.c_str() + field.size() );
    return -1;
  }

  inline double rate( const Rates &rates, const std::string &prefix )
  {
    for ( const auto &[name, value] : rates )
      if ( name.rfind( prefix, 0 ) == 0 )
        return value;
    return 0.0;
  }
}

#endif
