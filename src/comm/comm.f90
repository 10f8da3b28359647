!> The communication layer: every MPI call of mefem lives in this module.
!>
!> Physics and I/O code call verbs (comm_sum, comm_min, comm_bcast, ...) and never MPI
!> directly. A serial run is the same code on one rank. Libraries that need the
!> communicator (MUMPS, HDF5) get the Fortran integer handle from comm_fortran_handle().
module mefem_comm
  use mpi_f08
  use mefem_kinds, only: wp, i8
  implicit none
  private

  public :: comm_init, comm_finalize, comm_abort, comm_barrier
  public :: comm_rank, comm_size, comm_is_root, comm_fortran_handle, comm_wtime
  public :: comm_sum, comm_min, comm_max, comm_bcast, comm_exscan_sum
  public :: comm_allgather, comm_any, comm_gatherv_real, comm_gatherv_int
  public :: comm_info_null_handle

  integer :: my_rank = 0    !< rank of this process in the world communicator
  integer :: n_ranks = 1    !< number of ranks
  logical :: started = .false.

  !> Global sum over all ranks (in place).
  interface comm_sum
    module procedure sum_real, sum_real_array, sum_int, sum_int_array, sum_i8
  end interface comm_sum
  !> Global minimum over all ranks (in place).
  interface comm_min
    module procedure min_real, min_int
  end interface comm_min
  !> Global maximum over all ranks (in place).
  interface comm_max
    module procedure max_real, max_int
  end interface comm_max
  !> Broadcast from rank 0 to all ranks.
  interface comm_bcast
    module procedure bcast_int, bcast_int_array, bcast_real_array, bcast_logical, bcast_char
  end interface comm_bcast
  !> Gather one value of every rank on every rank.
  interface comm_allgather
    module procedure allgather_int, allgather_i8
  end interface comm_allgather

contains

  !> Start MPI (once) and record rank and size.
  subroutine comm_init()
    integer :: ierr
    logical :: already
    call MPI_Initialized(already, ierr)
    if (.not. already) call MPI_Init(ierr)
    call MPI_Comm_rank(MPI_COMM_WORLD, my_rank, ierr)
    call MPI_Comm_size(MPI_COMM_WORLD, n_ranks, ierr)
    started = .true.
  end subroutine comm_init

  !> Finish MPI cleanly.
  subroutine comm_finalize()
    integer :: ierr
    logical :: done
    if (.not. started) return
    call MPI_Finalized(done, ierr)
    if (.not. done) call MPI_Finalize(ierr)
    started = .false.
  end subroutine comm_finalize

  !> Abort all ranks with an exit code (used after a fatal error was printed).
  subroutine comm_abort(code)
    integer, intent(in) :: code   !< process exit code
    integer :: ierr
    call MPI_Abort(MPI_COMM_WORLD, code, ierr)
  end subroutine comm_abort

  !> Synchronise all ranks.
  subroutine comm_barrier()
    integer :: ierr
    call MPI_Barrier(MPI_COMM_WORLD, ierr)
  end subroutine comm_barrier

  !> Rank of this process (0-based).
  integer function comm_rank()
    comm_rank = my_rank
  end function comm_rank

  !> Number of ranks.
  integer function comm_size()
    comm_size = n_ranks
  end function comm_size

  !> True on rank 0, the rank that prints and writes histories.
  logical function comm_is_root()
    comm_is_root = (my_rank == 0)
  end function comm_is_root

  !> Fortran integer handle of the world communicator, for MUMPS and HDF5.
  integer function comm_fortran_handle()
    comm_fortran_handle = MPI_COMM_WORLD%MPI_VAL
  end function comm_fortran_handle

  !> Wall-clock time in seconds.
  real(wp) function comm_wtime()
    comm_wtime = MPI_Wtime()
  end function comm_wtime

  subroutine sum_real(x)
    real(wp), intent(inout) :: x   !< value, replaced by the global sum
    integer :: ierr
    call MPI_Allreduce(MPI_IN_PLACE, x, 1, MPI_DOUBLE_PRECISION, MPI_SUM, MPI_COMM_WORLD, ierr)
  end subroutine sum_real

  subroutine sum_real_array(x)
    real(wp), intent(inout) :: x(:)   !< values, replaced by the global sums
    integer :: ierr
    if (size(x) == 0) return
    call MPI_Allreduce(MPI_IN_PLACE, x, size(x), MPI_DOUBLE_PRECISION, MPI_SUM, &
                       MPI_COMM_WORLD, ierr)
  end subroutine sum_real_array

  subroutine sum_int(x)
    integer, intent(inout) :: x   !< value, replaced by the global sum
    integer :: ierr
    call MPI_Allreduce(MPI_IN_PLACE, x, 1, MPI_INTEGER, MPI_SUM, MPI_COMM_WORLD, ierr)
  end subroutine sum_int

  subroutine sum_int_array(x)
    integer, intent(inout) :: x(:)   !< values, replaced by the global sums
    integer :: ierr
    if (size(x) == 0) return
    call MPI_Allreduce(MPI_IN_PLACE, x, size(x), MPI_INTEGER, MPI_SUM, MPI_COMM_WORLD, ierr)
  end subroutine sum_int_array

  subroutine sum_i8(x)
    integer(i8), intent(inout) :: x   !< value, replaced by the global sum
    integer :: ierr
    call MPI_Allreduce(MPI_IN_PLACE, x, 1, MPI_INTEGER8, MPI_SUM, MPI_COMM_WORLD, ierr)
  end subroutine sum_i8

  subroutine min_real(x)
    real(wp), intent(inout) :: x   !< value, replaced by the global minimum
    integer :: ierr
    call MPI_Allreduce(MPI_IN_PLACE, x, 1, MPI_DOUBLE_PRECISION, MPI_MIN, MPI_COMM_WORLD, ierr)
  end subroutine min_real

  subroutine min_int(x)
    integer, intent(inout) :: x   !< value, replaced by the global minimum
    integer :: ierr
    call MPI_Allreduce(MPI_IN_PLACE, x, 1, MPI_INTEGER, MPI_MIN, MPI_COMM_WORLD, ierr)
  end subroutine min_int

  subroutine max_real(x)
    real(wp), intent(inout) :: x   !< value, replaced by the global maximum
    integer :: ierr
    call MPI_Allreduce(MPI_IN_PLACE, x, 1, MPI_DOUBLE_PRECISION, MPI_MAX, MPI_COMM_WORLD, ierr)
  end subroutine max_real

  subroutine max_int(x)
    integer, intent(inout) :: x   !< value, replaced by the global maximum
    integer :: ierr
    call MPI_Allreduce(MPI_IN_PLACE, x, 1, MPI_INTEGER, MPI_MAX, MPI_COMM_WORLD, ierr)
  end subroutine max_int

  !> True on every rank if the flag is true on any rank.
  logical function comm_any(flag)
    logical, intent(in) :: flag   !< this rank's flag
    integer :: ierr
    comm_any = flag
    call MPI_Allreduce(MPI_IN_PLACE, comm_any, 1, MPI_LOGICAL, MPI_LOR, MPI_COMM_WORLD, ierr)
  end function comm_any

  !> Exclusive prefix sum over ranks: offset of this rank's share in a global array.
  integer(i8) function comm_exscan_sum(n)
    integer(i8), intent(in) :: n   !< this rank's count
    integer :: ierr
    comm_exscan_sum = 0_i8
    call MPI_Exscan(n, comm_exscan_sum, 1, MPI_INTEGER8, MPI_SUM, MPI_COMM_WORLD, ierr)
    if (my_rank == 0) comm_exscan_sum = 0_i8
  end function comm_exscan_sum

  subroutine bcast_int(x)
    integer, intent(inout) :: x   !< value, from rank 0
    integer :: ierr
    call MPI_Bcast(x, 1, MPI_INTEGER, 0, MPI_COMM_WORLD, ierr)
  end subroutine bcast_int

  subroutine bcast_int_array(x)
    integer, intent(inout) :: x(:)   !< values, from rank 0
    integer :: ierr
    if (size(x) == 0) return
    call MPI_Bcast(x, size(x), MPI_INTEGER, 0, MPI_COMM_WORLD, ierr)
  end subroutine bcast_int_array

  subroutine bcast_real_array(x)
    real(wp), intent(inout) :: x(:)   !< values, from rank 0
    integer :: ierr
    if (size(x) == 0) return
    call MPI_Bcast(x, size(x), MPI_DOUBLE_PRECISION, 0, MPI_COMM_WORLD, ierr)
  end subroutine bcast_real_array

  subroutine bcast_logical(x)
    logical, intent(inout) :: x   !< value, from rank 0
    integer :: ierr
    call MPI_Bcast(x, 1, MPI_LOGICAL, 0, MPI_COMM_WORLD, ierr)
  end subroutine bcast_logical

  subroutine bcast_char(x)
    character(len=*), intent(inout) :: x   !< text, from rank 0
    integer :: ierr
    call MPI_Bcast(x, len(x), MPI_CHARACTER, 0, MPI_COMM_WORLD, ierr)
  end subroutine bcast_char

  subroutine allgather_int(x, all)
    integer, intent(in) :: x          !< this rank's value
    integer, intent(out) :: all(:)    !< values of ranks 0..n-1 (size comm_size())
    integer :: ierr
    call MPI_Allgather(x, 1, MPI_INTEGER, all, 1, MPI_INTEGER, MPI_COMM_WORLD, ierr)
  end subroutine allgather_int

  subroutine allgather_i8(x, all)
    integer(i8), intent(in) :: x          !< this rank's value
    integer(i8), intent(out) :: all(:)    !< values of ranks 0..n-1 (size comm_size())
    integer :: ierr
    call MPI_Allgather(x, 1, MPI_INTEGER8, all, 1, MPI_INTEGER8, MPI_COMM_WORLD, ierr)
  end subroutine allgather_i8

  !> Gather variable-length real arrays on rank 0 (concatenated in rank order).
  subroutine comm_gatherv_real(mine, all)
    real(wp), intent(in) :: mine(:)                  !< this rank's values
    real(wp), allocatable, intent(out) :: all(:)     !< on rank 0: all values; else empty
    integer :: counts(n_ranks), displs(n_ranks), ierr, r
    call MPI_Gather(size(mine), 1, MPI_INTEGER, counts, 1, MPI_INTEGER, 0, MPI_COMM_WORLD, ierr)
    if (my_rank == 0) then
      displs(1) = 0
      do r = 2, n_ranks
        displs(r) = displs(r-1) + counts(r-1)
      end do
      allocate(all(sum(counts)))
    else
      allocate(all(0))
    end if
    call MPI_Gatherv(mine, size(mine), MPI_DOUBLE_PRECISION, all, counts, displs, &
                     MPI_DOUBLE_PRECISION, 0, MPI_COMM_WORLD, ierr)
  end subroutine comm_gatherv_real

  !> Gather variable-length integer arrays on rank 0 (concatenated in rank order).
  subroutine comm_gatherv_int(mine, all)
    integer, intent(in) :: mine(:)                  !< this rank's values
    integer, allocatable, intent(out) :: all(:)     !< on rank 0: all values; else empty
    integer :: counts(n_ranks), displs(n_ranks), ierr, r
    call MPI_Gather(size(mine), 1, MPI_INTEGER, counts, 1, MPI_INTEGER, 0, MPI_COMM_WORLD, ierr)
    if (my_rank == 0) then
      displs(1) = 0
      do r = 2, n_ranks
        displs(r) = displs(r-1) + counts(r-1)
      end do
      allocate(all(sum(counts)))
    else
      allocate(all(0))
    end if
    call MPI_Gatherv(mine, size(mine), MPI_INTEGER, all, counts, displs, &
                     MPI_INTEGER, 0, MPI_COMM_WORLD, ierr)
  end subroutine comm_gatherv_int

  !> Fortran integer handle of MPI_INFO_NULL (no MPI-IO hints), for HDF5's MPI-IO driver.
  integer function comm_info_null_handle()
    comm_info_null_handle = MPI_INFO_NULL%MPI_VAL
  end function comm_info_null_handle

end module mefem_comm
