/* Experiment (benchmarks/mumps_ordering/run.py): give PETSc 3.18's MUMPS
   factor a user ordering (ICNTL(7) = 1, PERM_IN) under a Schur set.

   PETSc 3.18 takes a user ordering only for LU on one rank and refuses
   -mat_mumps_icntl_7 1; on one rank it also resets ICNTL(7) to 7 after
   MUMPS's initialisation. Both happen inside MatCholeskyFactorSymbolic,
   right before MUMPS's analysis, and the last thing that runs in between
   is the factor's ConvertToTriples function pointer. This file replaces
   that pointer with a wrapper that calls the original and then sets
   ICNTL(7) = 1 and PERM_IN. It needs PETSc 3.18.5's private Mat_MUMPS
   layout (copied below up to that pointer): an experiment, not the
   engine's code. */
#include <petsc/private/matimpl.h>
#include <dmumps_c.h>

typedef MUMPS_INT PetscMUMPSInt;
typedef struct Mat_MUMPS Mat_MUMPS;
struct Mat_MUMPS { /* PETSc 3.18.5 src/mat/impls/aij/mpi/mumps/mumps.c, up to ConvertToTriples */
  DMUMPS_STRUC_C id;
  MatStructure   matstruc;
  PetscMPIInt    myid, petsc_size;
  PetscMUMPSInt *irn, *jcn;
  PetscScalar   *val, *val_alloc;
  PetscInt64     nnz;
  PetscMUMPSInt  sym;
  MPI_Comm       mumps_comm;
  PetscMUMPSInt *ICNTL_pre;
  PetscReal     *CNTL_pre;
  PetscMUMPSInt  ICNTL9_pre;
  VecScatter     scat_rhs, scat_sol;
  PetscMUMPSInt  ICNTL20;
  PetscMUMPSInt  lrhs_loc, nloc_rhs, *irhs_loc;
#if defined(PETSC_HAVE_OPENMP_SUPPORT)
  PetscInt    *rhs_nrow, max_nrhs;
  PetscMPIInt *rhs_recvcounts, *rhs_disps;
  PetscScalar *rhs_loc, *rhs_recvbuf;
#endif
  Vec            b_seq, x_seq;
  PetscInt       ninfo, *info;
  PetscInt       sizeredrhs;
  PetscScalar   *schur_sol;
  PetscInt       schur_sizesol;
  PetscMUMPSInt *ia_alloc, *ja_alloc;
  PetscInt64     cur_ilen, cur_jlen;
  PetscErrorCode (*ConvertToTriples)(Mat, PetscInt, MatReuse, Mat_MUMPS *);
};

typedef PetscErrorCode (*convert_t)(Mat, PetscInt, MatReuse, Mat_MUMPS *);
static convert_t orig = NULL;
static PetscMUMPSInt *pending = NULL;
static int pending_set = 0;

static PetscErrorCode hook(Mat A, PetscInt shift, MatReuse reuse, Mat_MUMPS *m) {
  PetscErrorCode ierr = orig(A, shift, reuse, m);
  if (ierr) return ierr;
  if (reuse == MAT_INITIAL_MATRIX && pending_set) {
    m->id.icntl[6] = 1; /* ICNTL(7) = 1: PERM_IN */
    if (m->id.perm_in) { ierr = PetscFree(m->id.perm_in); if (ierr) return ierr; }
    m->id.perm_in = pending; /* host only; NULL elsewhere */
    pending = NULL; pending_set = 0;
  }
  return 0;
}

/* perm[i] = 1-based pivot position of variable i (host only; n = 0 on
   the other ranks), used by the next analysis of F */
int shim_order(Mat F, const PetscMUMPSInt *perm, PetscInt n) {
  Mat_MUMPS *m = (Mat_MUMPS *)F->data;
  PetscErrorCode ierr;
  if (m->ConvertToTriples != hook) { orig = m->ConvertToTriples; m->ConvertToTriples = hook; }
  if (pending) { ierr = PetscFree(pending); if (ierr) return ierr; }
  pending = NULL;
  if (n) {
    ierr = PetscMalloc1(n, &pending); if (ierr) return ierr;
    for (PetscInt i = 0; i < n; i++) pending[i] = perm[i];
  }
  pending_set = 1;
  return 0;
}
/* ICNTL(i) and INFOG(i) of the factor, read back */
int shim_get_icntl(Mat F, int i) { return ((DMUMPS_STRUC_C *)F->data)->icntl[i-1]; }
int shim_get_infog(Mat F, int i) { return ((DMUMPS_STRUC_C *)F->data)->infog[i-1]; }
