// The BLAS level-1 kernel the dense Newton paths call directly (OpenBLAS, Fortran interface):
// y += alpha x on contiguous rows, vectorised for the CPU at run time.
#pragma once

extern "C" void daxpy_(const int* n, const double* alpha, const double* x, const int* incx,
                       double* y, const int* incy);
