!> The communication layer: every MPI call of mefem lives in this module.
!>
!> Physics and I/O code call verbs (comm_sum, comm_min, comm_bcast, ...) and never MPI
!> directly. A serial run is the same code on one rank. Libraries that need the
!> communicator (MUMPS, HDF5) get the Fortran integer handle from comm_fortran_handle().
module mefem_comm
  use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_loc, c_f_pointer
  use, intrinsic :: iso_fortran_env, only: error_unit
  use mpi_f08
  use mefem_kinds, only: wp, i8
  implicit none
  private

  public :: comm_init, comm_finalize, comm_abort, comm_barrier
  public :: comm_rank, comm_size, comm_is_root, comm_fortran_handle, comm_wtime
  public :: comm_sum, comm_min, comm_max, comm_bcast, comm_exscan_sum
  public :: comm_allgather, comm_any, comm_gatherv_real, comm_gatherv_int
  public :: comm_info_null_handle, comm_allgatherv_real, comm_allgatherv_int
  public :: comm_arena_t, comm_arena_create, comm_arena_free, comm_arena_array, &
            comm_arena_peer_array, comm_arena_on_node, comm_arena_sync
  public :: comm_work_reset, comm_work_take, comm_work_steal, comm_work_finished, &
            comm_work_wait
  public :: comm_mail_post, comm_mail_wait_posted, comm_mail_read, comm_mail_wait_read
  public :: comm_min_request_t, comm_min_start, comm_min_progress, comm_min_finish

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

  !> A global minimum in flight (opaque): comm_min_start posts it, comm_min_finish waits for it
  !> and gives the result; work that needs neither the operand nor the result may run
  !> between (the ranks meet at the finish, not at the start).
  type :: comm_min_request_t
    private
    real(wp), allocatable :: value(:)                 !< (1) operand, then the minimum (on
                                                      !< the heap: it stays in place)
    type(MPI_Request) :: request                      !< the reduction's handle
    logical :: active = .false.                       !< started, not yet finished
  end type comm_min_request_t

  !> Pending non-blocking transfers (opaque): comm_isend_real and comm_irecv_real add one,
  !> comm_waitall completes them all. Keep one per exchange that may be in flight.
  public :: comm_requests_t, comm_isend_real, comm_irecv_real, comm_waitall
  type :: comm_requests_t
    private
    integer :: n = 0                                  !< transfers posted, not yet completed
    type(MPI_Request), allocatable :: list(:)         !< their handles
  end type comm_requests_t

  !> Node-shared memory (MPI-3 shared windows): each rank of a node has one segment that the
  !> other ranks of its node can read and write with plain loads and stores. A segment starts
  !> with a header of ARENA_HEADER_BYTES (the work-claiming words below), then the arrays the
  !> rank asked for, each ARENA_ALIGN-byte aligned. The segments are one window, so that one
  !> MPI_Win_sync orders every access (the window is locked for all ranks from creation to
  !> release: passive-target atomics on it need no further locking).
  !>
  !> Work claiming (comm_work_*): a rank's n work items (e.g. its cell blocks) are taken in
  !> chunks from the front by the rank itself and from the back by the other ranks of its
  !> node when they have run out of their own. One 64-bit word counts both ends, front +
  !> back * 2**32, and every claim is one atomic fetch-and-add on it, so no item is taken twice
  !> and none is left out (each claimant computes its range from the word's value before its
  !> own addition). The thieves add the count of the items they finished to a second word,
  !> after a memory barrier, and the owner waits for it before reading their results.
  !>
  !> Mail (comm_mail_*): a rank writes data into its segment for the other ranks of its node
  !> and posts a number (an exchange count); they wait until that number is posted, read the
  !> data in place and count their reads in the writer's header, which the writer waits for
  !> before it writes the next exchange's data. One exchange in flight per arena.
  type :: comm_arena_t
    private
    logical :: active = .false.                       !< created, not yet freed
    logical :: shared = .false.                       !< in a shared window (else, alone on
                                                      !< its node, in private memory)
    type(MPI_Win) :: win                              !< the node's shared window
    character(len=1), pointer, contiguous :: private_memory(:) => null()  !< the segment of a
                                                      !< rank alone on its node
    integer :: narray = 0                             !< arrays per segment
    integer :: node_size = 1                          !< ranks on this node
    integer, allocatable :: node_rank_of(:)           !< (world size) node rank of a world
                                                      !< rank, -1 if on another node
    integer(MPI_ADDRESS_KIND), allocatable :: offset(:,:)  !< (narray, node_size) byte offset
                                                      !< of array k in node rank r's segment
    type(c_ptr), allocatable :: segment(:)            !< (node_size) base of each segment
    integer(i8) :: items = 0                          !< owner: items of the current round
    integer(i8) :: chunk = 1                          !< owner: items per claim
  end type comm_arena_t

  integer, parameter :: ARENA_ALIGN = 64              !< alignment of arrays (a cache line)
  integer, parameter :: ARENA_HEADER_BYTES = 64       !< claim, done, item count, posted, read
  integer(MPI_ADDRESS_KIND), parameter :: WORD_CLAIM = 0, WORD_DONE = 1, WORD_ITEMS = 2
  integer(MPI_ADDRESS_KIND), parameter :: WORD_POSTED = 3, WORD_READ = 4  !< mail words
  integer(i8), parameter :: BACK_UNIT = 2_i8**32      !< one item taken from the back
  integer(MPI_ADDRESS_KIND), parameter :: WORD_BYTES = storage_size(0_i8)/8  !< header word
  type(MPI_Comm) :: node_comm                         !< the ranks sharing this node's memory
  logical :: have_node_comm = .false.

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

  !> Start the global minimum of x over all ranks (collective; every rank starts and finishes
  !> its reductions in the same order, as for blocking ones).
  subroutine comm_min_start(reduction, x)
    type(comm_min_request_t), intent(inout) :: reduction  !< not in flight
    real(wp), intent(in) :: x                         !< this rank's value
    integer :: ierr
    if (reduction%active) then
      write(error_unit, '(a)') 'mefem: error: comm_min_start: a minimum is in flight already'
      call MPI_Abort(MPI_COMM_WORLD, 1, ierr)
    end if
    if (.not. allocated(reduction%value)) allocate(reduction%value(1))
    reduction%value(1) = x
    call MPI_Iallreduce(MPI_IN_PLACE, reduction%value, 1, MPI_DOUBLE_PRECISION, MPI_MIN, &
                        MPI_COMM_WORLD, reduction%request, ierr)
    reduction%active = .true.
  end subroutine comm_min_start

  !> Let a minimum in flight advance without waiting (MPI moves a non-blocking reduction on
  !> only inside MPI calls: a rank that has the others' values passes them on here, instead
  !> of making them wait until it reaches comm_min_finish).
  subroutine comm_min_progress(reduction)
    type(comm_min_request_t), intent(inout) :: reduction  !< in flight (or finished)
    integer :: ierr
    logical :: done
    if (reduction%active) call MPI_Test(reduction%request, done, MPI_STATUS_IGNORE, ierr)
  end subroutine comm_min_progress

  !> Wait for a minimum started by comm_min_start; x = the minimum over all ranks.
  subroutine comm_min_finish(reduction, x)
    type(comm_min_request_t), intent(inout) :: reduction  !< in flight
    real(wp), intent(out) :: x                        !< the minimum
    integer :: ierr
    if (.not. reduction%active) then
      write(error_unit, '(a)') 'mefem: error: comm_min_finish: no minimum in flight'
      call MPI_Abort(MPI_COMM_WORLD, 1, ierr)
    end if
    call MPI_Wait(reduction%request, MPI_STATUS_IGNORE, ierr)
    reduction%active = .false.
    x = reduction%value(1)
  end subroutine comm_min_finish

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

  !> Concatenate variable-length integer arrays of all ranks, in rank order, on every rank
  !> (as comm_allgatherv_real; no second collective when the total is 0).
  subroutine comm_allgatherv_int(mine, n_mine, all, n_all)
    integer, intent(in) :: mine(:)                   !< this rank's values (1:n_mine used)
    integer, intent(in) :: n_mine                    !< values of this rank
    integer, allocatable, intent(inout) :: all(:)    !< all ranks' values (1:n_all), kept
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
    if (n_all == 0) return
    call MPI_Allgatherv(mine, n_mine, MPI_INTEGER, all, counts, displs, MPI_INTEGER, &
                        MPI_COMM_WORLD, ierr)
  end subroutine comm_allgatherv_int

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


  !> Create an arena (collective over all ranks): this rank's segment holds arrays of
  !> bytes(k) bytes each (sizes may differ between ranks; the same number of arrays on every
  !> rank). comm_arena_array gives their addresses.
  subroutine comm_arena_create(arena, bytes)
    type(comm_arena_t), intent(out) :: arena          !< the new arena
    integer(i8), intent(in) :: bytes(:)               !< size of each array (bytes)
    integer(MPI_ADDRESS_KIND) :: total, peer_size
    integer(MPI_ADDRESS_KIND), allocatable :: mine(:)
    integer :: k, r, node_rank, ierr, disp_unit
    integer, allocatable :: world_of(:)
    type(c_ptr) :: base
    if (.not. have_node_comm) then
      call MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, my_rank, MPI_INFO_NULL, &
                               node_comm, ierr)
      have_node_comm = .true.
    end if
    call MPI_Comm_size(node_comm, arena%node_size, ierr)
    call MPI_Comm_rank(node_comm, node_rank, ierr)
    arena%narray = size(bytes)
    allocate(mine(arena%narray), arena%offset(arena%narray, arena%node_size))
    ! room for the header, the arrays rounded up to whole lines, and the shift that aligns the
    ! first array (the segment itself may start anywhere)
    total = ARENA_HEADER_BYTES + ARENA_ALIGN
    do k = 1, arena%narray
      total = total + ((int(bytes(k), MPI_ADDRESS_KIND) + ARENA_ALIGN - 1)/ARENA_ALIGN)*ARENA_ALIGN
    end do
    allocate(world_of(arena%node_size), arena%node_rank_of(n_ranks), arena%segment(arena%node_size))
    call MPI_Allgather(my_rank, 1, MPI_INTEGER, world_of, 1, MPI_INTEGER, node_comm, ierr)
    arena%node_rank_of = -1
    do r = 1, arena%node_size
      arena%node_rank_of(world_of(r) + 1) = r - 1
    end do
    ! a rank alone on its node keeps its segment in private memory: a shared window is backed
    ! by a file in /dev/shm, which a container may keep small, and nobody would share it
    arena%shared = arena%node_size > 1
    if (arena%shared) then
      call MPI_Win_allocate_shared(total, 1, MPI_INFO_NULL, node_comm, base, arena%win, ierr)
    else
      allocate(arena%private_memory(total))
      base = c_loc(arena%private_memory(1))
    end if
    mine(1) = ARENA_HEADER_BYTES + modulo(-address_of(base) - ARENA_HEADER_BYTES, &
                                          int(ARENA_ALIGN, MPI_ADDRESS_KIND))
    do k = 2, arena%narray
      mine(k) = mine(k - 1) + ((int(bytes(k - 1), MPI_ADDRESS_KIND) + ARENA_ALIGN - 1)/ &
                               ARENA_ALIGN)*ARENA_ALIGN
    end do
    call MPI_Allgather(mine, arena%narray, MPI_AINT, arena%offset, arena%narray, MPI_AINT, &
                       node_comm, ierr)
    if (arena%shared) then
      do r = 1, arena%node_size
        call MPI_Win_shared_query(arena%win, r - 1, peer_size, disp_unit, arena%segment(r), &
                                  ierr)
      end do
      call MPI_Win_lock_all(MPI_MODE_NOCHECK, arena%win, ierr)
    else
      arena%segment(1) = base
    end if
    call put_word(arena, node_rank, WORD_CLAIM, 0_i8)
    call put_word(arena, node_rank, WORD_DONE, 0_i8)
    call put_word(arena, node_rank, WORD_ITEMS, 0_i8)
    call put_word(arena, node_rank, WORD_POSTED, 0_i8)
    call put_word(arena, node_rank, WORD_READ, 0_i8)
    call comm_arena_sync(arena)
    call MPI_Barrier(node_comm, ierr)
    arena%active = .true.
  end subroutine comm_arena_create

  !> Release an arena (collective over all ranks; nothing may use its arrays afterwards).
  subroutine comm_arena_free(arena)
    type(comm_arena_t), intent(inout) :: arena        !< the arena
    integer :: ierr
    if (.not. arena%active) return
    if (arena%shared) then
      call MPI_Win_unlock_all(arena%win, ierr)
      call MPI_Win_free(arena%win, ierr)
    else
      deallocate(arena%private_memory)
    end if
    arena%active = .false.
  end subroutine comm_arena_free

  !> Address of this rank's array k.
  function comm_arena_array(arena, k) result(address)
    type(comm_arena_t), intent(in) :: arena           !< the arena
    integer, intent(in) :: k                          !< array (order of comm_arena_create)
    type(c_ptr) :: address
    address = comm_arena_peer_array(arena, my_rank, k)
  end function comm_arena_array

  !> Address of array k of world rank `rank` (c_null_ptr if that rank is on another node).
  function comm_arena_peer_array(arena, rank, k) result(address)
    type(comm_arena_t), intent(in) :: arena           !< the arena
    integer, intent(in) :: rank                       !< world rank (0-based)
    integer, intent(in) :: k                          !< array
    type(c_ptr) :: address
    integer :: node_rank
    address = c_null_ptr
    if (.not. arena%active) return
    node_rank = arena%node_rank_of(rank + 1)
    if (node_rank < 0) return
    address = byte_offset(arena%segment(node_rank + 1), arena%offset(k, node_rank + 1))
  end function comm_arena_peer_array

  !> Whether world rank `rank` shares this node's memory (always true for this rank).
  logical function comm_arena_on_node(arena, rank)
    type(comm_arena_t), intent(in) :: arena           !< the arena
    integer, intent(in) :: rank                       !< world rank (0-based)
    comm_arena_on_node = .false.
    if (arena%active) comm_arena_on_node = arena%node_rank_of(rank + 1) >= 0
  end function comm_arena_on_node

  !> Make this rank's stores to the arena visible to the node's other ranks and theirs to
  !> this rank (a memory barrier: MPI_Win_sync), e.g. around a barrier after set-up.
  subroutine comm_arena_sync(arena)
    type(comm_arena_t), intent(inout) :: arena        !< the arena
    integer :: ierr
    if (arena%shared) call MPI_Win_sync(arena%win, ierr)
  end subroutine comm_arena_sync

  !> Owner: start a round of n work items, claimed `chunk` at a time. Call after the data the
  !> thieves read were written (the reset orders them before any claim of this round).
  subroutine comm_work_reset(arena, n, chunk)
    type(comm_arena_t), intent(inout) :: arena        !< the arena
    integer, intent(in) :: n                          !< work items of this round
    integer, intent(in) :: chunk                      !< items per claim (>= 1)
    integer :: node_rank
    node_rank = arena%node_rank_of(my_rank + 1)
    arena%items = int(n, i8)
    arena%chunk = int(max(chunk, 1), i8)
    call comm_arena_sync(arena)
    call put_word(arena, node_rank, WORD_DONE, 0_i8)
    call put_word(arena, node_rank, WORD_ITEMS, arena%items)
    call put_word(arena, node_rank, WORD_CLAIM, 0_i8)
  end subroutine comm_work_reset

  !> Owner: the next chunk of its own items from the front, items first..last (1-based); last
  !> < first when none is left (then the owner waits for the thieves: comm_work_wait).
  subroutine comm_work_take(arena, first, last)
    type(comm_arena_t), intent(inout) :: arena        !< the arena
    integer, intent(out) :: first, last               !< the items taken
    integer(i8) :: old, front, back
    old = add_word(arena, arena%node_rank_of(my_rank + 1), WORD_CLAIM, arena%chunk)
    front = iand(old, BACK_UNIT - 1)
    back = old/BACK_UNIT
    first = int(front + 1)
    last = int(min(front + arena%chunk, arena%items - back))
  end subroutine comm_work_take

  !> Thief: a chunk of `chunk` items of world rank `rank` (same node) from the back, items
  !> first..last of that rank; last < first when it has none left. The items' data are
  !> readable once this returns a range.
  subroutine comm_work_steal(arena, rank, chunk, first, last)
    type(comm_arena_t), intent(inout) :: arena        !< the arena
    integer, intent(in) :: rank                       !< the owner (world rank, 0-based)
    integer, intent(in) :: chunk                      !< items per claim (>= 1)
    integer, intent(out) :: first, last               !< the items taken
    integer(i8) :: old, front, back, items
    integer :: node_rank
    first = 1
    last = 0
    node_rank = arena%node_rank_of(rank + 1)
    if (node_rank < 0 .or. rank == my_rank) return
    items = add_word(arena, node_rank, WORD_ITEMS, 0_i8)
    old = add_word(arena, node_rank, WORD_CLAIM, int(max(chunk, 1), i8)*BACK_UNIT)
    front = iand(old, BACK_UNIT - 1)
    back = old/BACK_UNIT
    last = int(items - back)
    first = int(max(items - back - int(max(chunk, 1), i8) + 1, front + 1))
    call comm_arena_sync(arena)
  end subroutine comm_work_steal

  !> Thief: count items of world rank `rank` done (their results written before this call).
  subroutine comm_work_finished(arena, rank, count)
    type(comm_arena_t), intent(inout) :: arena        !< the arena
    integer, intent(in) :: rank                       !< the owner (world rank, 0-based)
    integer, intent(in) :: count                      !< items finished
    integer(i8) :: old
    call comm_arena_sync(arena)
    old = add_word(arena, arena%node_rank_of(rank + 1), WORD_DONE, int(count, i8))
  end subroutine comm_work_finished

  !> Owner: wait until the thieves have finished `stolen` of its items (the round's items
  !> less those it took itself); their results are readable when this returns.
  subroutine comm_work_wait(arena, stolen)
    type(comm_arena_t), intent(inout) :: arena        !< the arena
    integer, intent(in) :: stolen                     !< items the thieves took
    call wait_for_word(arena, arena%node_rank_of(my_rank + 1), WORD_DONE, int(stolen, i8))
  end subroutine comm_work_wait

  !> Writer: the data of exchange `count` are in this rank's segment (readable by the node's
  !> other ranks once they see the count).
  subroutine comm_mail_post(arena, count)
    type(comm_arena_t), intent(inout) :: arena        !< the arena
    integer(i8), intent(in) :: count                  !< the exchange's number (1, 2, ...)
    call comm_arena_sync(arena)
    call put_word(arena, arena%node_rank_of(my_rank + 1), WORD_POSTED, count)
  end subroutine comm_mail_post

  !> Reader: wait until world rank `rank` (same node) has posted exchange `count`; its data
  !> are readable when this returns.
  subroutine comm_mail_wait_posted(arena, rank, count)
    type(comm_arena_t), intent(inout) :: arena        !< the arena
    integer, intent(in) :: rank                       !< the writer (world rank, 0-based)
    integer(i8), intent(in) :: count                  !< the exchange's number
    call wait_for_word(arena, arena%node_rank_of(rank + 1), WORD_POSTED, count)
  end subroutine comm_mail_wait_posted

  !> Reader: done reading what world rank `rank` (same node) posted.
  subroutine comm_mail_read(arena, rank)
    type(comm_arena_t), intent(inout) :: arena        !< the arena
    integer, intent(in) :: rank                       !< the writer (world rank, 0-based)
    integer(i8) :: old
    call comm_arena_sync(arena)
    old = add_word(arena, arena%node_rank_of(rank + 1), WORD_READ, 1_i8)
  end subroutine comm_mail_read

  !> Writer: wait until this rank's posts have been read `reads` times in all (e.g. exchanges
  !> so far x readers), so that its data may be overwritten.
  subroutine comm_mail_wait_read(arena, reads)
    type(comm_arena_t), intent(inout) :: arena        !< the arena
    integer(i8), intent(in) :: reads                  !< reads to wait for
    call wait_for_word(arena, arena%node_rank_of(my_rank + 1), WORD_READ, reads)
  end subroutine comm_mail_wait_read

  !> Wait until header word `word` of node rank `node_rank` is at least `at_least` (other
  !> ranks raise it), then order this rank's later loads after it (memory barrier).
  subroutine wait_for_word(arena, node_rank, word, at_least)
    type(comm_arena_t), intent(inout) :: arena        !< the arena
    integer, intent(in) :: node_rank                  !< whose header
    integer(MPI_ADDRESS_KIND), intent(in) :: word     !< word index in the header
    integer(i8), intent(in) :: at_least               !< value waited for
    integer :: ierr
    logical :: arrived
    do while (add_word(arena, node_rank, word, 0_i8) < at_least)
      ! MPI progress: with more ranks than cores Open MPI yields the core here
      call MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, arrived, MPI_STATUS_IGNORE, &
                      ierr)
    end do
    call comm_arena_sync(arena)
  end subroutine wait_for_word

  !> Atomically add `value` to header word `word` of node rank `node_rank`; the old value.
  function add_word(arena, node_rank, word, value) result(old)
    type(comm_arena_t), intent(inout) :: arena        !< the arena
    integer, intent(in) :: node_rank                  !< whose header
    integer(MPI_ADDRESS_KIND), intent(in) :: word     !< word index in the header
    integer(i8), intent(in) :: value                  !< added (0: an atomic read)
    integer(i8) :: old
    old = word_operation(arena, node_rank, word, value, MPI_SUM)
  end function add_word

  !> Atomically set header word `word` of node rank `node_rank`.
  subroutine put_word(arena, node_rank, word, value)
    type(comm_arena_t), intent(inout) :: arena        !< the arena
    integer, intent(in) :: node_rank                  !< whose header
    integer(MPI_ADDRESS_KIND), intent(in) :: word     !< word index in the header
    integer(i8), intent(in) :: value                  !< the new value
    integer(i8) :: old
    old = word_operation(arena, node_rank, word, value, MPI_REPLACE)
  end subroutine put_word

  !> One atomic operation (MPI_SUM or MPI_REPLACE) on a header word, completed; the old value.
  function word_operation(arena, node_rank, word, value, operation) result(old)
    type(comm_arena_t), intent(inout) :: arena        !< the arena
    integer, intent(in) :: node_rank                  !< whose header
    integer(MPI_ADDRESS_KIND), intent(in) :: word     !< word index in the header
    integer(i8), intent(in) :: value                  !< operand
    type(MPI_Op), intent(in) :: operation             !< MPI_SUM or MPI_REPLACE
    integer(i8) :: old
    integer(i8), pointer :: words(:)
    integer :: ierr
    if (arena%shared) then
      call MPI_Fetch_and_op(value, old, MPI_INTEGER8, node_rank, word*WORD_BYTES, operation, &
                            arena%win, ierr)
      call MPI_Win_flush(node_rank, arena%win, ierr)
    else                                  ! alone on the node: plain memory
      call c_f_pointer(arena%segment(1), words, [int(ARENA_HEADER_BYTES/WORD_BYTES)])
      old = words(word + 1)
      if (operation == MPI_SUM) then
        words(word + 1) = old + value
      else
        words(word + 1) = value
      end if
    end if
  end function word_operation

  !> A C address as an integer.
  integer(MPI_ADDRESS_KIND) function address_of(base)
    type(c_ptr), intent(in) :: base                   !< the address
    integer :: ierr
    character(len=1), pointer :: memory(:)
    call c_f_pointer(base, memory, [1])
    call MPI_Get_address(memory(1), address_of, ierr)
  end function address_of

  !> The address `bytes` past `base`.
  function byte_offset(base, bytes) result(address)
    type(c_ptr), intent(in) :: base                   !< start address
    integer(MPI_ADDRESS_KIND), intent(in) :: bytes    !< offset
    type(c_ptr) :: address
    character(len=1), pointer :: memory(:)
    call c_f_pointer(base, memory, [bytes + 1])
    address = c_loc(memory(bytes + 1))
  end function byte_offset
end module mefem_comm
