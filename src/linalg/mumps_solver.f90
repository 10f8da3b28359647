!> The direct sparse solver: a thin wrapper of MUMPS (double precision, MPI).
!>
!> This is the only file of mefem that calls MUMPS. The communicator comes from mefem_comm.
!> Every routine here is collective: all ranks call it, with their own share of the matrix.
!>
!> Use:  mumps_init (once) -> mumps_analyse (pattern) -> mumps_factorise (values)
!>       -> mumps_solve (any number of right-hand sides) -> ... -> mumps_free.
!> When the values change but the positions do not (Newton iterations with
!> coo_reset_values), call mumps_factorise again: it re-analyses by itself only when the
!> matrix's pattern_id differs from the analysed one (on any rank).
!>
!> Input: distributed assembled matrix (ICNTL(18) = 3). Each rank passes its own COO
!> triplets, in any split and with duplicates (MUMPS sums them). The triplets are copied
!> into arrays owned by the solver (MUMPS needs the indices again at factorisation), so the
!> caller may reuse or free its coo_matrix_t meanwhile; the copy costs 16 bytes per entry.
!> For SYM = 1 or 2 the matrix must hold only its lower triangle (coo_add_block with
!> symmetric = .true.); for SYM = 0 the whole matrix. A mismatch is reported as an error.
!>
!> Ordering: Debian's MUMPS 5.5.1 is built without METIS and SCOTCH; asking ICNTL(7) = 5
!> silently falls back to another ordering (AMF on a 20^3 Laplacian, PORD on 60^3). So the
!> default here is METIS's nested dissection computed by mefem (ORDERING_METIS_ND): rank 0
!> gathers the pattern of all ranks' entries, mefem_metis orders its symmetrised graph with
!> METIS_NodeND, and MUMPS gets the order as the user's (ICNTL(7) = 1, PERM_IN). On the
!> plasticity benchmark's 50 385 ME-FEM unknowns it gave 24.8 M entries in the factors and
!> a 2.55 s factorisation against 35.3 M and 4.84 s with PORD (ICNTL(7) = 4, the nested
!> dissection shipped with MUMPS, the default before; on a 3D 7-point Laplacian of 60^3
!> unknowns PORD gave 85 M entries against 125 M with AMF and 164 M with AMD or QAMD). PORD,
!> AMD, AMF and QAMD can be chosen with the optional `ordering` argument of mumps_init.
!> INFOG(7) (stats%ordering_used) tells which ordering was really used.
!>
!> Singular matrices (checked with MUMPS 5.5.1, see tests/unit/test_mumps_solver.f90):
!> - an unknown with no entry (zero row and column) gives INFOG(1) = -10 in SPD mode and a
!>   null pivot (below) in the other modes;
!> - null pivot detection (ICNTL(24) = 1, |pivot| <= 1e-12 ||A||; relative, checked on
!>   matrices scaled by 1e8 and 1e-15) finds the roundoff-size pivots of a singular but
!>   consistent matrix (pure Neumann Laplacian, an unconstrained rigid-body mode) in the
!>   unsymmetric and general symmetric modes (INFOG(28) > 0);
!> - in SPD mode (SYM = 1) MUMPS does not detect null pivots; such a matrix factorises and
!>   gives one of its solutions, unless its last pivot comes out negative (INFOG(12) > 0),
!>   which is reported as "not positive definite". Use MUMPS_SYMMETRIC where unconstrained
!>   models must be diagnosed reliably.
!> All of these are returned as status%ok = .false. with a message, never a stop.
!>
!> Output of MUMPS is silenced unless the environment variable MEFEM_MUMPS_VERBOSE=1.
module mefem_mumps
  use mefem_kinds, only: wp, i8
  use mefem_comm, only: comm_fortran_handle, comm_is_root, comm_bcast, comm_wtime, comm_any, &
                        comm_gatherv_int
  use mefem_metis, only: metis_nested_dissection
  use mefem_index_lists, only: counts_to_starts
  use mefem_errors, only: status_t
  use mefem_sparse_assembly, only: coo_matrix_t, STORAGE_EMPTY, STORAGE_FULL, STORAGE_LOWER
  implicit none
  private

  include 'dmumps_struc.h'

  public :: mumps_init, mumps_analyse, mumps_factorise, mumps_solve, mumps_free, mumps_stats
  public :: ordering_name

  !> Kinds of matrix (MUMPS SYM).
  integer, parameter, public :: MUMPS_UNSYMMETRIC = 0   !< general matrix, LU
  integer, parameter, public :: MUMPS_SPD = 1           !< symmetric positive definite, LDL^T
  integer, parameter, public :: MUMPS_SYMMETRIC = 2     !< general symmetric (indefinite), LDL^T

  !> Fill-reducing orderings (MUMPS ICNTL(7) values).
  integer, parameter, public :: ORDERING_AMD = 0    !< approximate minimum degree
  !> METIS nested dissection (METIS_NodeND) computed here on rank 0 from the gathered
  !> pattern and given to MUMPS as the user's pivot order (ICNTL(7) = 1, PERM_IN)
  integer, parameter, public :: ORDERING_METIS_ND = 1
  integer, parameter, public :: ORDERING_AMF = 2    !< approximate minimum fill
  integer, parameter, public :: ORDERING_PORD = 4   !< PORD nested dissection
  integer, parameter, public :: ORDERING_METIS = 5  !< METIS (falls back to AMF on Debian)
  integer, parameter, public :: ORDERING_QAMD = 6   !< AMD with quasi-dense row detection
  integer, parameter, public :: ORDERING_AUTO = 7   !< MUMPS chooses

  !> Default: a pivot below this times the norm of the matrix counts as zero (singular).
  real(wp), parameter :: NULL_PIVOT_RELATIVE = 1.0e-12_wp

  !> MUMPS job codes.
  integer, parameter :: JOB_INIT = -1, JOB_END = -2
  integer, parameter :: JOB_ANALYSE = 1, JOB_FACTORISE = 2, JOB_SOLVE = 3

  interface
    !> The MUMPS driver (double precision).
    subroutine dmumps(id)
      import :: dmumps_struc
      type(dmumps_struc), intent(inout) :: id   !< MUMPS instance
    end subroutine dmumps
  end interface

  !> Figures of the last analysis, factorisation and solve (the same on every rank).
  type, public :: mumps_stats_t
    real(wp) :: time_analysis = 0.0_wp        !< wall time of the last analysis (s)
    real(wp) :: time_factorisation = 0.0_wp   !< wall time of the last factorisation (s)
    real(wp) :: time_solve = 0.0_wp           !< wall time of the last solve (s)
    integer :: n_analyses = 0                 !< analyses done since mumps_init
    integer :: n_factorisations = 0           !< factorisations done since mumps_init
    integer :: n_solves = 0                   !< solves done since mumps_init
    integer(i8) :: factor_entries_estimated = 0_i8  !< INFOG(3): entries in factors (analysis)
    integer(i8) :: factor_entries = 0_i8      !< INFOG(9): entries in factors (factorisation)
    integer :: memory_max_mb = 0              !< INFOG(21): MB used in factorisation, max rank
    integer :: memory_total_mb = 0            !< INFOG(22): MB used in factorisation, all ranks
    integer :: ordering_used = -1             !< INFOG(7): ORDERING_* really used
    integer :: negative_pivots = 0            !< INFOG(12) for SYM = 1, 2 (0 for SYM = 0)
  end type mumps_stats_t

  !> One MUMPS instance and what it was given (opaque: use the routines of this module).
  type, public :: mumps_solver_t
    private
    type(dmumps_struc) :: id                  !< the MUMPS structure
    logical :: initialised = .false.          !< after a successful mumps_init
    logical :: analysed = .false.             !< after a successful analysis
    logical :: factorised = .false.           !< after a successful factorisation
    integer :: n = 0                          !< size of the analysed matrix
    integer(i8) :: pattern_id = -1_i8         !< pattern_id of the analysed matrix (this rank)
    type(mumps_stats_t) :: stats              !< timings and figures
  end type mumps_solver_t

contains

  !> Start a MUMPS instance on all ranks of the world communicator.
  subroutine mumps_init(s, symmetric_kind, status, ordering, null_pivot_tolerance)
    type(mumps_solver_t), intent(inout) :: s      !< the solver
    integer, intent(in) :: symmetric_kind         !< MUMPS_UNSYMMETRIC, MUMPS_SPD, MUMPS_SYMMETRIC
    type(status_t), intent(out) :: status         !< failure with a message
    integer, intent(in), optional :: ordering     !< ORDERING_* (default ORDERING_METIS_ND)
    !> pivots below this times ||A|| make the matrix singular (default 1e-12; <= 0: no check;
    !> not used by MUMPS in SPD mode)
    real(wp), intent(in), optional :: null_pivot_tolerance
    character(len=8) :: verbose
    integer :: length, env_status
    if (s%initialised) call mumps_free(s)
    if (symmetric_kind < MUMPS_UNSYMMETRIC .or. symmetric_kind > MUMPS_SYMMETRIC) then
      call fail(status, 'mumps_init: unknown matrix kind (SYM) ', symmetric_kind)
      return
    end if
    s%id%comm = comm_fortran_handle()
    s%id%sym = symmetric_kind
    s%id%par = 1                        ! the host rank works too
    s%id%job = JOB_INIT
    call dmumps(s%id)
    if (s%id%infog(1) < 0) then
      call fail(status, 'MUMPS initialisation failed, INFOG(1) = ', s%id%infog(1))
      return
    end if
    s%initialised = .true.
    s%stats = mumps_stats_t()
    call get_environment_variable('MEFEM_MUMPS_VERBOSE', verbose, length, env_status)
    if (env_status /= 0 .or. trim(verbose) /= '1') then
      s%id%icntl(1) = -1                ! error messages
      s%id%icntl(2) = -1                ! diagnostics and warnings
      s%id%icntl(3) = -1                ! global information
      s%id%icntl(4) = 0                 ! print level
    end if
    s%id%icntl(5) = 0                   ! assembled matrix
    s%id%icntl(7) = ORDERING_METIS_ND
    if (present(ordering)) s%id%icntl(7) = ordering
    s%id%icntl(14) = 50                 ! 50 % extra working space (default 20, or 30 for SYM=2)
    s%id%icntl(18) = 3                  ! distributed assembled input
    s%id%icntl(20) = 0                  ! dense right-hand side
    s%id%icntl(21) = 0                  ! centralised solution (on rank 0)
    s%id%icntl(28) = 1                  ! sequential analysis (no ParMETIS/PT-SCOTCH here)
    s%id%icntl(24) = 1                  ! detect null pivots (reported as singular, below)
    s%id%cntl(3) = -NULL_PIVOT_RELATIVE ! null pivot: |pivot| <= NULL_PIVOT_RELATIVE * ||A||
    if (present(null_pivot_tolerance)) then
      s%id%cntl(3) = -null_pivot_tolerance
      if (null_pivot_tolerance <= 0.0_wp) s%id%icntl(24) = 0
    end if
    nullify(s%id%irn_loc, s%id%jcn_loc, s%id%a_loc, s%id%rhs, s%id%perm_in)
  end subroutine mumps_init

  !> Symbolic analysis (ordering, elimination tree) of the pattern of a.
  subroutine mumps_analyse(s, a, status)
    type(mumps_solver_t), intent(inout) :: s   !< the solver, initialised
    type(coo_matrix_t), intent(in) :: a        !< this rank's entries (positions used)
    type(status_t), intent(out) :: status      !< failure with a message
    integer(i8) :: nnz
    real(wp) :: start
    s%analysed = .false.
    s%factorised = .false.
    if (.not. s%initialised) then
      status%ok = .false.
      status%message = 'mumps_analyse: solver used before mumps_init'
      return
    end if
    call check_input(s, a, status)
    if (.not. status%ok) return
    call release_matrix(s)
    nnz = a%nnz
    allocate(s%id%irn_loc(nnz), s%id%jcn_loc(nnz), s%id%a_loc(nnz))
    s%id%irn_loc(:) = a%row(1:nnz)
    s%id%jcn_loc(:) = a%col(1:nnz)
    s%id%a_loc(:) = 0.0_wp
    s%id%n = a%n                          ! needed on the host; set on every rank
    s%id%nnz_loc = nnz
    start = comm_wtime()
    if (s%id%icntl(7) == ORDERING_METIS_ND) then
      call metis_pivot_order(s, a, status)
      if (.not. status%ok) return
    end if
    s%id%job = JOB_ANALYSE
    call dmumps(s%id)
    s%stats%time_analysis = comm_wtime() - start
    s%stats%n_analyses = s%stats%n_analyses + 1
    if (s%id%infog(1) < 0) then
      call mumps_failure(s, 'analysis', status)
      return
    end if
    s%n = a%n
    s%pattern_id = a%pattern_id
    s%analysed = .true.
    s%stats%ordering_used = s%id%infog(7)
    s%stats%factor_entries_estimated = mumps_count(s%id%infog(3))
  end subroutine mumps_analyse

  !> Numerical factorisation with the current values of a; re-analyses first if the
  !> pattern of a changed on any rank since the last analysis.
  subroutine mumps_factorise(s, a, status)
    type(mumps_solver_t), intent(inout) :: s   !< the solver, initialised
    type(coo_matrix_t), intent(in) :: a        !< this rank's entries
    type(status_t), intent(out) :: status      !< failure with a message
    real(wp) :: start
    if (comm_any(.not. s%analysed .or. a%pattern_id /= s%pattern_id)) then
      call mumps_analyse(s, a, status)
      if (.not. status%ok) return
    end if
    s%factorised = .false.
    s%id%a_loc(:) = a%val(1:s%id%nnz_loc)
    start = comm_wtime()
    s%id%job = JOB_FACTORISE
    call dmumps(s%id)
    s%stats%time_factorisation = comm_wtime() - start
    s%stats%n_factorisations = s%stats%n_factorisations + 1
    if (s%id%infog(1) < 0) then
      call mumps_failure(s, 'factorisation', status)
      return
    end if
    if (s%id%infog(28) > 0) then
      call null_pivot_failure(s, status)
      return
    end if
    if (s%id%sym == MUMPS_SPD .and. s%id%infog(12) > 0) then
      call fail(status, 'linear solver factorisation failed: matrix declared SPD is not '// &
          'positive definite (singular or unstable: rigid-body motion not constrained? '// &
          'use MUMPS_SYMMETRIC for indefinite matrices); negative pivots: ', s%id%infog(12))
      return
    end if
    s%factorised = .true.
    s%stats%factor_entries = mumps_count(s%id%infog(9))
    s%stats%memory_max_mb = s%id%infog(21)
    s%stats%memory_total_mb = s%id%infog(22)
    s%stats%negative_pivots = 0
    if (s%id%sym /= MUMPS_UNSYMMETRIC) s%stats%negative_pivots = s%id%infog(12)
  end subroutine mumps_factorise

  !> Solve A x = rhs with the last factorisation. The right-hand side is read on rank 0
  !> only (other ranks may pass any array, even of size 0); the solution is broadcast, so
  !> every rank returns the full x(1:n).
  subroutine mumps_solve(s, rhs, x, status)
    type(mumps_solver_t), intent(inout) :: s   !< the solver, factorised
    real(wp), intent(in) :: rhs(:)             !< right-hand side, size n, on rank 0
    real(wp), intent(out) :: x(:)              !< solution, size n, on every rank
    type(status_t), intent(out) :: status      !< failure with a message
    real(wp) :: start
    integer :: bad
    if (.not. s%factorised) then
      status%ok = .false.
      status%message = 'mumps_solve: no valid factorisation (factorise first, or it failed)'
      return
    end if
    bad = 0
    if (size(x) /= s%n) bad = 1
    if (comm_is_root() .and. size(rhs) /= s%n) bad = 1
    if (comm_any(bad /= 0)) then
      call fail(status, 'mumps_solve: rhs (rank 0) and x must have the matrix size ', s%n)
      return
    end if
    start = comm_wtime()
    if (comm_is_root()) then
      allocate(s%id%rhs(s%n))
      s%id%rhs(:) = rhs(1:s%n)
    else
      allocate(s%id%rhs(0))
    end if
    s%id%nrhs = 1
    s%id%lrhs = s%n
    s%id%job = JOB_SOLVE
    call dmumps(s%id)
    if (s%id%infog(1) >= 0 .and. comm_is_root()) x(:) = s%id%rhs(1:s%n)
    deallocate(s%id%rhs)
    nullify(s%id%rhs)
    if (s%id%infog(1) < 0) then
      call mumps_failure(s, 'solve', status)
      return
    end if
    call comm_bcast(x)
    s%stats%time_solve = comm_wtime() - start
    s%stats%n_solves = s%stats%n_solves + 1
  end subroutine mumps_solve

  !> Release the MUMPS instance and the solver's copies of the matrix.
  subroutine mumps_free(s)
    type(mumps_solver_t), intent(inout) :: s   !< the solver
    if (.not. s%initialised) return
    call release_matrix(s)
    s%id%job = JOB_END
    call dmumps(s%id)
    s%initialised = .false.
    s%analysed = .false.
    s%factorised = .false.
    s%pattern_id = -1_i8
  end subroutine mumps_free

  !> Timings and figures of the last phases.
  type(mumps_stats_t) function mumps_stats(s)
    type(mumps_solver_t), intent(in) :: s   !< the solver
    mumps_stats = s%stats
  end function mumps_stats

  !> Name of an ordering code (ICNTL(7) / INFOG(7) value).
  function ordering_name(code) result(name)
    integer, intent(in) :: code              !< ORDERING_* value
    character(len=:), allocatable :: name
    select case (code)
    case (ORDERING_AMD)
      name = 'AMD'
    case (ORDERING_METIS_ND)
      name = 'METIS nested dissection (given)'
    case (ORDERING_AMF)
      name = 'AMF'
    case (3)
      name = 'SCOTCH'
    case (ORDERING_PORD)
      name = 'PORD'
    case (ORDERING_METIS)
      name = 'METIS'
    case (ORDERING_QAMD)
      name = 'QAMD'
    case (ORDERING_AUTO)
      name = 'automatic'
    case default
      name = 'unknown'
    end select
  end function ordering_name

  !> Check (collectively) that the matrix has unknowns and its storage fits the solver's SYM.
  subroutine check_input(s, a, status)
    type(mumps_solver_t), intent(in) :: s    !< the solver
    type(coo_matrix_t), intent(in) :: a      !< this rank's entries
    type(status_t), intent(inout) :: status  !< set on failure
    logical :: wrong, storage_fits
    if (s%id%sym == MUMPS_UNSYMMETRIC) then
      wrong = a%storage /= STORAGE_EMPTY .and. a%storage /= STORAGE_FULL
      storage_fits = .not. comm_any(wrong)
      if (.not. storage_fits) status%message = 'mumps_analyse: unsymmetric solver (SYM=0) '// &
          'needs whole blocks, but lower triangles (symmetric=.true.) were added'
    else
      wrong = a%storage /= STORAGE_EMPTY .and. a%storage /= STORAGE_LOWER
      storage_fits = .not. comm_any(wrong)
      if (.not. storage_fits) status%message = 'mumps_analyse: symmetric solver (SYM=1,2) '// &
          'needs lower triangles only (coo_add_block with symmetric=.true.)'
    end if
    if (storage_fits .and. comm_any(a%n <= 0)) then
      status%message = 'mumps_analyse: matrix has no unknowns (coo_init not called?)'
      storage_fits = .false.
    end if
    status%ok = storage_fits
  end subroutine check_input

  !> Free the solver's copies of the matrix.
  subroutine release_matrix(s)
    type(mumps_solver_t), intent(inout) :: s   !< the solver
    if (associated(s%id%irn_loc)) deallocate(s%id%irn_loc)
    if (associated(s%id%jcn_loc)) deallocate(s%id%jcn_loc)
    if (associated(s%id%a_loc)) deallocate(s%id%a_loc)
    if (associated(s%id%perm_in)) deallocate(s%id%perm_in)
    nullify(s%id%irn_loc, s%id%jcn_loc, s%id%a_loc, s%id%perm_in)
  end subroutine release_matrix

  !> PERM_IN on the host: METIS nested dissection of the symmetrised pattern of all ranks'
  !> entries: each rank's distinct off-diagonal pairs, gathered on rank 0, where the repeats
  !> between ranks are dropped and each vertex's neighbours put in ascending order, so the
  !> same pattern gives the same order on any number of ranks. Collective; a failure on
  !> rank 0 is reported on every rank.
  subroutine metis_pivot_order(s, a, status)
    type(mumps_solver_t), intent(inout) :: s   !< the solver (n set, PERM_IN not allocated)
    type(coo_matrix_t), intent(in) :: a        !< this rank's entries
    type(status_t), intent(out) :: status      !< failure with a message
    integer, allocatable :: low(:), high(:), all_low(:), all_high(:), start(:), neighbours(:)
    character(len=200) :: message
    call unique_pairs(a%n, a%row(1:a%nnz), a%col(1:a%nnz), low, high)
    call comm_gatherv_int(low, all_low)
    call comm_gatherv_int(high, all_high)
    message = ''
    if (comm_is_root()) then
      call unique_pairs(a%n, all_low, all_high, low, high)
      deallocate(all_low, all_high)
      call sorted_graph(a%n, low, high, start, neighbours)
      allocate(s%id%perm_in(a%n))
      call metis_nested_dissection(a%n, start, neighbours, s%id%perm_in, status)
      if (.not. status%ok) message = status%message
    end if
    call comm_bcast(message)
    status%ok = len_trim(message) == 0
    status%message = trim(message)
  end subroutine metis_pivot_order

  !> The graph of distinct pairs low < high (grouped by ascending low, as unique_pairs gives
  !> them) in CSR form with both directions, each vertex's neighbours ascending: first its
  !> lower neighbours (appended pair by pair), then its upper ones (every vertex j, in
  !> ascending order, appends itself to the lists of its lower neighbours).
  subroutine sorted_graph(n, low, high, start, neighbours)
    integer, intent(in) :: n                          !< vertices
    integer, intent(in) :: low(:), high(:)            !< distinct pairs, ascending low
    integer, allocatable, intent(out) :: start(:)     !< (n+1) vertex i's neighbours are
    integer, allocatable, intent(out) :: neighbours(:) !< neighbours(start(i):start(i+1)-1)
    integer, allocatable :: next(:)
    integer :: k, i, j, m
    allocate(start(n + 1), next(n))
    next = 0
    do k = 1, size(low)
      next(low(k)) = next(low(k)) + 1
      next(high(k)) = next(high(k)) + 1
    end do
    call counts_to_starts(next, start, 1)
    allocate(neighbours(start(n + 1) - 1))
    do k = 1, size(low)
      neighbours(next(high(k))) = low(k)
      next(high(k)) = next(high(k)) + 1
    end do
    do j = 1, n                                  ! (next(j): end of j's lower neighbours)
      do m = start(j), next(j) - 1
        i = neighbours(m)
        neighbours(next(i)) = j
        next(i) = next(i) + 1
      end do
    end do
  end subroutine sorted_graph

  !> The distinct off-diagonal positions of a list of entries as pairs low < high (an entry
  !> and its transpose give one pair): a counting sort by the lower index, repeats dropped in
  !> place, so that only the distinct pairs are gathered.
  subroutine unique_pairs(n, row, col, low, high)
    integer, intent(in) :: n                          !< matrix size
    integer, intent(in) :: row(:), col(:)             !< the entries' positions
    integer, allocatable, intent(out) :: low(:), high(:)  !< the distinct pairs
    integer, allocatable :: start(:), next(:), partner(:), last_low(:)
    integer :: k, i, m, npair, first
    allocate(start(n + 1), next(n), last_low(n))
    next = 0                                  ! partners per lower index
    do k = 1, size(row)
      if (row(k) /= col(k)) next(min(row(k), col(k))) = next(min(row(k), col(k))) + 1
    end do
    call counts_to_starts(next, start, 1)
    allocate(partner(start(n + 1) - 1))
    do k = 1, size(row)
      if (row(k) == col(k)) cycle
      i = min(row(k), col(k))
      partner(next(i)) = max(row(k), col(k))
      next(i) = next(i) + 1
    end do
    last_low = 0                              ! distinct partners, moved forward in place
    npair = 0
    do i = 1, n
      first = npair + 1
      do m = start(i), start(i + 1) - 1
        if (last_low(partner(m)) == i) cycle
        last_low(partner(m)) = i
        npair = npair + 1
        partner(npair) = partner(m)
      end do
      next(i) = npair - first + 1             ! distinct partners of i
    end do
    allocate(low(npair), high(npair))
    npair = 0
    do i = 1, n
      do m = 1, next(i)
        npair = npair + 1
        low(npair) = i
        high(npair) = partner(npair)
      end do
    end do
  end subroutine unique_pairs

  !> Turn INFOG(1) < 0 into a status with a readable message.
  subroutine mumps_failure(s, phase, status)
    type(mumps_solver_t), intent(in) :: s      !< the solver after the failed call
    character(len=*), intent(in) :: phase      !< 'analysis', 'factorisation' or 'solve'
    type(status_t), intent(inout) :: status    !< set to failure
    character(len=64) :: codes
    character(len=:), allocatable :: what
    write(codes, '(a,i0,a,i0,a)') ' (MUMPS INFOG(1) = ', s%id%infog(1), ', INFOG(2) = ', &
        s%id%infog(2), ')'
    select case (s%id%infog(1))
    case (-10)
      what = 'matrix is singular (rigid-body motion not constrained?)'
    case (-6)
      what = 'matrix is structurally singular (an unknown with no stiffness: '// &
          'rigid-body motion not constrained, or an unused dof?)'
    case (-40)
      what = 'matrix declared positive definite has a negative or zero pivot: '// &
          'use the general symmetric kind (SYM=2) or check constraints'
    case (-8, -9, -11, -12, -14, -15, -17, -20)
      what = 'MUMPS internal workspace too small: increase ICNTL(14) (now 50 %)'
    case (-5, -7, -13)
      what = 'out of memory in MUMPS: use more ranks (more total memory), a smaller model, '// &
          'or another ordering'
    case (-19)
      what = 'MUMPS memory limit ICNTL(23) too small'
    case (-16)
      what = 'matrix size N out of range'
    case (-2)
      what = 'number of entries out of range'
    case (-4)
      what = 'invalid ordering permutation'
    case default
      what = 'MUMPS error'
    end select
    status%ok = .false.
    status%message = 'linear solver '//phase//' failed: '//what//trim(codes)
  end subroutine mumps_failure

  !> Report null pivots found in the factorisation as a singular matrix.
  subroutine null_pivot_failure(s, status)
    type(mumps_solver_t), intent(in) :: s      !< the solver after the factorisation
    type(status_t), intent(inout) :: status    !< set to failure
    character(len=160) :: text
    integer :: first
    first = 0
    if (comm_is_root()) first = s%id%pivnul_list(1)
    call comm_bcast(first)
    write(text, '(a,i0,a,i0,a)') ' (', s%id%infog(28), ' zero pivots, first at unknown ', first, ')'
    status%ok = .false.
    status%message = 'linear solver factorisation failed: matrix is singular '// &
        '(rigid-body motion not constrained?)'//trim(text)
  end subroutine null_pivot_failure

  !> A failure with a message and one integer.
  subroutine fail(status, message, value)
    type(status_t), intent(out) :: status   !< set to failure
    character(len=*), intent(in) :: message !< text
    integer, intent(in) :: value            !< appended number
    character(len=16) :: number
    write(number, '(i0)') value
    status%ok = .false.
    status%message = message//trim(number)
  end subroutine fail

  !> An INFOG count: negative values are in millions.
  integer(i8) function mumps_count(value)
    integer, intent(in) :: value   !< INFOG entry
    if (value >= 0) then
      mumps_count = int(value, i8)
    else
      mumps_count = -int(value, i8)*1000000_i8
    end if
  end function mumps_count

end module mefem_mumps
