/***************************************************************************
  schurcovariance.cpp - marginal covariances of a bundle-structured problem
 ***************************************************************************/
#include "adjustment/schurcovariance.h"

#include <Eigen/Dense>
#include <ceres/ceres.h>

namespace geostation
{

  SchurCovariance schurCovariance( ceres::Problem &problem, const std::vector<double *> &cameraBlocks, const std::vector<double *> &pointBlocks )
  {
    SchurCovariance result;
    ceres::Problem::EvaluateOptions options;
    options.apply_loss_function = false;
    options.parameter_blocks = cameraBlocks;
    options.parameter_blocks.insert( options.parameter_blocks.end(), pointBlocks.begin(), pointBlocks.end() );

    int cameraColumns = 0;
    for ( double *block : cameraBlocks )
    {
      result.cameraOffsets.push_back( cameraColumns );
      cameraColumns += problem.ParameterBlockTangentSize( block );
    }
    // Column -> (point index, column within the point), for the point part.
    std::vector<int> pointOfColumn, pointColumn;
    std::vector<int> pointSize;
    for ( size_t j = 0; j < pointBlocks.size(); ++j )
    {
      const int size = problem.ParameterBlockTangentSize( pointBlocks[j] );
      pointSize.push_back( size );
      for ( int k = 0; k < size; ++k )
      {
        pointOfColumn.push_back( static_cast<int>( j ) );
        pointColumn.push_back( k );
      }
    }

    ceres::CRSMatrix jacobian;
    if ( !problem.Evaluate( options, nullptr, nullptr, nullptr, &jacobian ) )
      return result;

    Eigen::MatrixXd U = Eigen::MatrixXd::Zero( cameraColumns, cameraColumns );
    std::vector<Eigen::MatrixXd> W( pointBlocks.size() ), V( pointBlocks.size() );
    for ( size_t j = 0; j < pointBlocks.size(); ++j )
    {
      W[j] = Eigen::MatrixXd::Zero( cameraColumns, pointSize[j] );
      V[j] = Eigen::MatrixXd::Zero( pointSize[j], pointSize[j] );
    }

    std::vector<std::pair<int, double>> cameraEntries;
    std::vector<std::pair<int, double>> pointEntries;
    for ( int row = 0; row < jacobian.num_rows; ++row )
    {
      cameraEntries.clear();
      pointEntries.clear();
      int point = -1;
      for ( int k = jacobian.rows[row]; k < jacobian.rows[row + 1]; ++k )
      {
        const int column = jacobian.cols[k];
        if ( column < cameraColumns )
          cameraEntries.emplace_back( column, jacobian.values[k] );
        else
        {
          point = pointOfColumn[column - cameraColumns];
          pointEntries.emplace_back( pointColumn[column - cameraColumns], jacobian.values[k] );
        }
      }
      for ( const auto &[ca, va] : cameraEntries )
      {
        for ( const auto &[cb, vb] : cameraEntries )
          U( ca, cb ) += va * vb;
        for ( const auto &[pb, vb] : pointEntries )
          W[point]( ca, pb ) += va * vb;
      }
      for ( const auto &[pa, va] : pointEntries )
        for ( const auto &[pb, vb] : pointEntries )
          V[point]( pa, pb ) += va * vb;
    }

    // S = U - sum W_j V_j^-1 W_j^T
    std::vector<Eigen::MatrixXd> vInverse( pointBlocks.size() );
    Eigen::MatrixXd S = U;
    for ( size_t j = 0; j < pointBlocks.size(); ++j )
    {
      Eigen::LDLT<Eigen::MatrixXd> ldlt( V[j] );
      if ( ldlt.info() != Eigen::Success || !( ldlt.vectorD().minCoeff() > 1e-14 * std::max( 1.0, ldlt.vectorD().maxCoeff() ) ) )
        return result;
      vInverse[j] = ldlt.solve( Eigen::MatrixXd::Identity( pointSize[j], pointSize[j] ) );
      S.noalias() -= W[j] * vInverse[j] * W[j].transpose();
    }
    if ( cameraColumns > 0 )
    {
      // Condition check on the Jacobi-scaled S.
      const Eigen::VectorXd scale = S.diagonal().cwiseMax( 1e-300 ).cwiseSqrt().cwiseInverse();
      const Eigen::MatrixXd scaled = scale.asDiagonal() * S * scale.asDiagonal();
      const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen( scaled, Eigen::EigenvaluesOnly );
      if ( !( eigen.eigenvalues()( 0 ) > 1e-12 * eigen.eigenvalues().maxCoeff() ) )
        return result;
      result.cameras = scale.asDiagonal() * scaled.inverse() * scale.asDiagonal();
    }
    result.points.resize( pointBlocks.size() );
    for ( size_t j = 0; j < pointBlocks.size(); ++j )
    {
      const Eigen::MatrixXd B = W[j] * vInverse[j];
      result.points[j] = vInverse[j] + ( cameraColumns > 0 ? Eigen::MatrixXd( B.transpose() * result.cameras * B ) : Eigen::MatrixXd::Zero( pointSize[j], pointSize[j] ) );
    }
    result.ok = true;
    return result;
  }

} // namespace geostation
