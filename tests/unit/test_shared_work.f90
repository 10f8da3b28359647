!> Unit test of the node-shared arena and its work claiming (mefem_comm: comm_arena_*,
!> comm_work_*), on 1 to 4 ranks of one node:
!> - every rank's arrays, of sizes that differ between ranks, are aligned, do not overlap the
!>   header or each other, and can be read by every other rank through its peer address;
!> - rounds of work claiming: each rank takes its items from the front while all ranks steal
!>   from each other's backs once their own are done; every item of every rank is taken
!>   exactly once, the thieves' results are all there when the owner's wait returns, and with
!>   a slowed owner (rank 0 waits after its first chunk until a thief has finished an item)
!>   items are stolen.
! ranks: 1 2 3 4
program test_shared_work
  use, intrinsic :: iso_c_binding, only: c_f_pointer, c_intptr_t, c_loc
  use mefem_kinds, only: wp, i8
  use mefem_comm, only: comm_rank, comm_size, comm_sum, comm_barrier, &
      comm_arena_t, comm_arena_create, comm_arena_free, comm_arena_array, &
      comm_arena_peer_array, comm_arena_on_node, comm_work_reset, comm_work_take, &
      comm_work_steal, comm_work_finished, comm_work_wait
  use mefem_testing, only: test_start, test_finish, check
  implicit none

  integer, parameter :: ROUNDS = 6
  type(comm_arena_t) :: arena
  integer :: rank, nranks

  call test_start('shared_work')
  rank = comm_rank()
  nranks = comm_size()
  call check_arrays()
  call check_claiming()
  call test_finish()

contains

  !> Items of `r` (a world rank) in a round: different for every rank and round.
  pure integer function items_of(r, round)
    integer, intent(in) :: r, round   !< rank, round
    items_of = 500 + 97*r + 31*round
  end function items_of

  !> Arrays of sizes that differ between ranks: alignment, no overlap, visible to all ranks.
  subroutine check_arrays()
    type(comm_arena_t) :: a
    real(wp), pointer :: x(:)
    integer, pointer :: m(:)
    integer :: r, i, nx, nm
    integer(c_intptr_t) :: px, pm
    logical :: ok_values, ok_layout
    nx = 100 + 13*rank
    nm = 7*rank + 3
    call comm_arena_create(a, [int(nx, i8)*8_i8, int(nm, i8)*4_i8])
    call c_f_pointer(comm_arena_array(a, 1), x, [nx])
    call c_f_pointer(comm_arena_array(a, 2), m, [nm])
    x = [(1000.0_wp*rank + i, i = 1, nx)]
    m = [(-100*rank - i, i = 1, nm)]
    px = transfer(c_loc(x(1)), px)
    pm = transfer(c_loc(m(1)), pm)
    ok_layout = mod(px, 64_c_intptr_t) == 0 .and. mod(pm, 64_c_intptr_t) == 0 .and. &
                pm >= px + 8*nx
    call check(ok_layout, 'arrays 64-byte aligned, the second after the first')
    call check(comm_arena_on_node(a, rank), 'this rank is on its node')
    call comm_barrier()                   ! all written before anyone reads
    ok_values = .true.
    do r = 0, nranks - 1
      if (.not. comm_arena_on_node(a, r)) cycle
      call c_f_pointer(comm_arena_peer_array(a, r, 1), x, [100 + 13*r])
      call c_f_pointer(comm_arena_peer_array(a, r, 2), m, [7*r + 3])
      ok_values = ok_values .and. all(x == [(1000.0_wp*r + i, i = 1, 100 + 13*r)]) .and. &
                  all(m == [(-100*r - i, i = 1, 7*r + 3)])
    end do
    call check(ok_values, 'every rank reads every rank''s arrays through the peer addresses')
    call comm_barrier()
    call comm_arena_free(a)
  end subroutine check_arrays

  !> Rounds of claiming with stealing: each item is marked by whoever computes it (a count and
  !> the value the owner expects), in the owner's array; checked by the owner after its wait.
  subroutine check_claiming()
    integer, pointer :: mark(:), peer_mark(:)
    integer(i8), pointer :: result_of(:), peer_result(:)
    integer :: round, first, last, i, r, n, victim, tries, stolen_here
    integer :: total_stolen_from_0, own_count
    logical :: exactly_once, results_there
    call comm_arena_create(arena, [int(items_of(rank, ROUNDS), i8)*4_i8, &
                                   int(items_of(rank, ROUNDS), i8)*8_i8])
    call c_f_pointer(comm_arena_array(arena, 1), mark, [items_of(rank, ROUNDS)])
    call c_f_pointer(comm_arena_array(arena, 2), result_of, [items_of(rank, ROUNDS)])
    exactly_once = .true.
    results_there = .true.
    total_stolen_from_0 = 0
    do round = 1, ROUNDS
      n = items_of(rank, round)
      mark(1:n) = 0
      result_of(1:n) = 0
      call comm_work_reset(arena, n, 3)
      call comm_barrier()                 ! every rank's round is open (as the time-step
                                          ! reduction orders the cycles of the solver)
      ! own items from the front; rank 0 waits after its first chunk until a thief has finished
      ! one of its items, so that stealing is sure to happen on more than one rank
      own_count = 0
      do
        call comm_work_take(arena, first, last)
        if (last < first) exit
        do i = first, last
          mark(i) = mark(i) + 1
          result_of(i) = expected_result(rank, round, i)
        end do
        if (rank == 0 .and. nranks > 1 .and. own_count == 0) call comm_work_wait(arena, 1)
        own_count = own_count + last - first + 1
      end do
      ! then the other ranks' items from their backs, round-robin until all are gone
      stolen_here = 0
      tries = 0
      do while (tries < nranks - 1)
        tries = 0
        do r = 1, nranks - 1
          victim = mod(rank + r, nranks)
          call comm_work_steal(arena, victim, 2, first, last)
          if (last < first) then
            tries = tries + 1
            cycle
          end if
          call c_f_pointer(comm_arena_peer_array(arena, victim, 1), peer_mark, &
                           [items_of(victim, ROUNDS)])
          call c_f_pointer(comm_arena_peer_array(arena, victim, 2), peer_result, &
                           [items_of(victim, ROUNDS)])
          do i = first, last
            peer_mark(i) = peer_mark(i) + 1
            peer_result(i) = expected_result(victim, round, i)
          end do
          call comm_work_finished(arena, victim, last - first + 1)
          if (victim == 0) stolen_here = stolen_here + last - first + 1
        end do
      end do
      call comm_work_wait(arena, n - own_count)
      exactly_once = exactly_once .and. all(mark(1:n) == 1)
      results_there = results_there .and. &
                      all(result_of(1:n) == [(expected_result(rank, round, i), i = 1, n)])
      call comm_sum(stolen_here)
      total_stolen_from_0 = total_stolen_from_0 + stolen_here
      call comm_barrier()                 ! nobody steals from the next round early
    end do
    call check(exactly_once, 'every item of every round taken exactly once')
    call check(results_there, 'the thieves'' results are all there after the owner''s wait')
    if (nranks > 1) call check(total_stolen_from_0 > 0, 'items of the slowed rank 0 stolen')
    call comm_barrier()
    call comm_arena_free(arena)
  end subroutine check_claiming

  !> The value item i of rank r gets in a round (who computes it must not matter).
  pure integer(i8) function expected_result(r, round, i)
    integer, intent(in) :: r, round, i   !< owner, round, item
    expected_result = int(r, i8)*1000000_i8 + int(round, i8)*10000_i8 + int(i, i8)
  end function expected_result

end program test_shared_work
