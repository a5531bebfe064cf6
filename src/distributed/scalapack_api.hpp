// The parts of ScaLAPACK, PBLAS and the C interface of BLACS that bemsurg calls (Debian's
// libscalapack-openmpi ships no C header: issue 41, item 4). Fortran routines take every argument
// by address; descriptors are 9 ints (ScaLAPACK Users' Guide, "Array descriptors").
#pragma once

#include <mpi.h>

extern "C" {
int Csys2blacs_handle(MPI_Comm comm);
void Cfree_blacs_system_handle(int handle);
void Cblacs_gridinit(int* context, const char* order, int process_rows, int process_columns);
void Cblacs_gridinfo(int context, int* process_rows, int* process_columns, int* my_row, int* my_column);
void Cblacs_gridexit(int context);
void descinit_(int* desc, const int* m, const int* n, const int* mb, const int* nb, const int* irsrc, const int* icsrc, const int* context,
               const int* lld, int* info);
void pdgetrf_(const int* m, const int* n, double* a, const int* ia, const int* ja, const int* desca, int* ipiv, int* info);
void pdgetrs_(const char* trans, const int* n, const int* nrhs, const double* a, const int* ia, const int* ja, const int* desca,
              const int* ipiv, double* b, const int* ib, const int* jb, const int* descb, int* info);
void pdgemv_(const char* trans, const int* m, const int* n, const double* alpha, const double* a, const int* ia, const int* ja,
             const int* desca, const double* x, const int* ix, const int* jx, const int* descx, const int* incx, const double* beta,
             double* y, const int* iy, const int* jy, const int* descy, const int* incy);
}
