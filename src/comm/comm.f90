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
  public :: comm_info_null_handle, comm_allgatherv_real

  integer :: my_rank = 0    !< rank of this process in the world communicator
  integer :: n_ranks = 1    !< number of ranks
  logical :: started = .false.

  !> Global sum over all ranks (in place).
  interface comm_sum
    module procedure sum_real, sum_real_array, sum_real_matrix, sum_int, sum_int_array, sum_i8
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

  !> Pending non-blocking transfers (opaque): comm_isend_real and comm_irecv_real add one,
  !> comm_waitall completes them all. Keep one per exchange that may be in flight.
  public :: comm_requests_t, comm_isend_real, comm_irecv_real, comm_waitall
  type :: comm_requests_t
    private
    integer :: n = 0                                  !< transfers posted, not yet completed
    type(MPI_Request), allocatable :: list(:)         !< their handles
  end type comm_requests_t

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

  subroutine sum_real_matrix(x)
    real(wp), intent(inout), contiguous :: x(:,:)   !< values, replaced by the global sums
    integer :: ierr
    if (size(x) == 0) return
    call MPI_Allreduce(MPI_IN_PLACE, x, size(x), MPI_DOUBLE_PRECISION, MPI_SUM, &
                       MPI_COMM_WORLD, ierr)
  end subroutine sum_real_matrix

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

  !> Concatenate variable-length real arrays of all ranks, in rank order, on every rank:
  !> all(1:n_all) = [mine(1:n_mine) of rank 0, of rank 1, ...]. all is reallocated only when
  !> it is too small (it then gets room for 3/2 of the total, so slowly growing totals do not
  !> reallocate every call). Two collectives: the counts (allgather), then the values.
  subroutine comm_allgatherv_real(mine, n_mine, all, n_all)
    real(wp), intent(in) :: mine(:)                  !< this rank's values (1:n_mine used)
    integer, intent(in) :: n_mine                    !< values of this rank
    real(wp), allocatable, intent(inout) :: all(:)   !< all ranks' values (1:n_all), kept
    integer, intent(out) :: n_all                    !< total count
    integer :: counts(n_ranks), displs(n_ranks), ierr, r
    call MPI_Allgather(n_mine, 1, MPI_INTEGER, counts, 1, MPI_INTEGER, MPI_COMM_WORLD, ierr)
    displs(1) = 0
    do r = 2, n_ranks
      displs(r) = displs(r-1) + counts(r-1)
    end do
    n_all = sum(counts)
    if (allocated(all)) then
      if (size(all) < n_all) deallocate(all)
    end if
    if (.not. allocated(all)) allocate(all(max(1, n_all + n_all/2)))
    call MPI_Allgatherv(mine, n_mine, MPI_DOUBLE_PRECISION, all, counts, displs, &
                        MPI_DOUBLE_PRECISION, MPI_COMM_WORLD, ierr)
  end subroutine comm_allgatherv_real

  !> Fortran integer handle of MPI_INFO_NULL (no MPI-IO hints), for HDF5's MPI-IO driver.
  integer function comm_info_null_handle()
    comm_info_null_handle = MPI_INFO_NULL%MPI_VAL
  end function comm_info_null_handle

  !> Post a non-blocking send of a real array to rank `destination`. The buffer must stay
  !> unchanged (and allocated) until comm_waitall on the same requests returns.
  subroutine comm_isend_real(buffer, destination, tag, requests)
    real(wp), intent(in), asynchronous, contiguous :: buffer(:) !< values to send
    integer, intent(in) :: destination                  !< receiving rank
    integer, intent(in) :: tag                          !< message tag (matches the receive)
    type(comm_requests_t), intent(inout) :: requests    !< the new request is appended
    integer :: ierr
    call grow_requests(requests)
    requests%n = requests%n + 1
    call MPI_Isend(buffer, size(buffer), MPI_DOUBLE_PRECISION, destination, tag, &
                   MPI_COMM_WORLD, requests%list(requests%n), ierr)
  end subroutine comm_isend_real

  !> Post a non-blocking receive of a real array from rank `source` (exactly size(buffer)
  !> values). The buffer holds the message once comm_waitall on the same requests returns.
  subroutine comm_irecv_real(buffer, source, tag, requests)
    real(wp), intent(inout), asynchronous, contiguous :: buffer(:) !< receives the values
    integer, intent(in) :: source                       !< sending rank
    integer, intent(in) :: tag                          !< message tag (matches the send)
    type(comm_requests_t), intent(inout) :: requests    !< the new request is appended
    integer :: ierr
    call grow_requests(requests)
    requests%n = requests%n + 1
    call MPI_Irecv(buffer, size(buffer), MPI_DOUBLE_PRECISION, source, tag, &
                   MPI_COMM_WORLD, requests%list(requests%n), ierr)
  end subroutine comm_irecv_real

  !> Wait until every transfer posted on `requests` has completed, then empty the list.
  subroutine comm_waitall(requests)
    type(comm_requests_t), intent(inout) :: requests    !< posted transfers; empty on return
    integer :: ierr
    if (requests%n > 0) call MPI_Waitall(requests%n, requests%list(1:requests%n), &
                                         MPI_STATUSES_IGNORE, ierr)
    requests%n = 0
  end subroutine comm_waitall

  !> Make room for one more request handle (the list doubles when full).
  subroutine grow_requests(requests)
    type(comm_requests_t), intent(inout) :: requests    !< request list
    type(MPI_Request), allocatable :: bigger(:)
    if (.not. allocated(requests%list)) allocate(requests%list(8))
    if (requests%n < size(requests%list)) return
    allocate(bigger(2*size(requests%list)))
    bigger(1:requests%n) = requests%list(1:requests%n)
    call move_alloc(bigger, requests%list)
  end subroutine grow_requests

end module mefem_comm
