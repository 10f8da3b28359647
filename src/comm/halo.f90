!> Mesh-aware halo exchange on top of the communication verbs of mefem_comm (no MPI here).
!>
!> A halo_t is built once from a decomposition or an explicit layout (neighbour ranks and, per
!> neighbour, the local nodes both hold, in the same order on both sides) with its buffers.
!> Two operations on nodal arrays f(ncomp, nnode_local):
!>
!> halo_sum: f holds this rank's partial sums; afterwards every rank holds, at every shared
!>   node, the sum of all ranks' partials. Each rank sends its partials and, at each shared
!>   node, adds the partials of all ranks holding the node in ascending rank order, its own
!>   in its place, starting from the lowest rank's value. So every copy of a shared node is
!>   bit-identical on every rank (no drift between copies), independent of message arrival.
!>   The partials themselves depend on how the elements are split, so the result may differ
!>   in the last bits between runs on different numbers of ranks.
!>
!> halo_assemble (layouts only): bit-identical for any number of ranks. The input is the
!>   per-cell contributions cell_values(ncomp, slots, ncell_local) (cell l's value for its j-th
!>   node, cells%nodes order); each local node gets the sum of all contributions to it, from
!>   every rank's cells, summed per chunk in ascending global cell order and over the chunks
!>   in ascending chunk order (the plan of mefem_explicit_layout), exactly what a one-rank run
!>   adds. The nodal array has the layout's ntarget columns: the nodes', then the partial
!>   sums of nodes touched by several chunks. _start sums this rank's contributions into
!>   their columns and sends the neighbours the sums they need (one per shared node and own
!>   chunk); _finish receives theirs and adds every node's chunk sums in chunk order.
!> Both come split into _start (post receives, pack and post sends) and _finish (wait, add),
!> so that other work can run in between; halo_sum's partials at shared nodes must be final
!> at its start (compute the cells touching shared nodes first; call halo_sum_start; compute
!> the others; call halo_sum_finish), halo_assemble's contributions all at its start.
!> Between start and finish, halo_sum needs f unchanged at shared nodes and halo_assemble
!> needs f unchanged.
!> Halos whose exchanges may be in flight at the same time must have different tags.
!>
!> halo_assembly_share_on_node (collective, once after halo_build) moves the assembly's buffer
!> into node-shared memory (mefem_comm's arena): then the neighbours on this node take the
!> sums packed for them straight from this rank's buffer (comm_mail_*: posted when
!> packed, read once by each of them before anything writes the buffer again) and only the
!> neighbours on other nodes get messages. The same values are summed in the same
!> order either way: the same bits.
module mefem_halo
  use, intrinsic :: iso_c_binding, only: c_f_pointer
  use mefem_kinds, only: wp, i8
  use mefem_errors, only: fatal_local
  use mefem_comm, only: comm_requests_t, comm_isend_real, comm_irecv_real, comm_waitall, &
                        comm_wtime, comm_barrier, comm_arena_t, comm_arena_create, &
                        comm_arena_free, comm_arena_array, comm_arena_peer_array, &
                        comm_arena_on_node, comm_arena_sync, comm_mail_post, &
                        comm_mail_wait_posted, comm_mail_read, comm_mail_wait_read
  use mefem_decomposition, only: decomposition_t
  use mefem_explicit_layout, only: explicit_layout_t
  implicit none
  private

  public :: halo_build, halo_sum, halo_sum_start, halo_sum_finish
  public :: halo_assemble, halo_assemble_start, halo_assemble_finish, halo_assembly_push_nodes
  public :: halo_assemble_summed
  public :: halo_gather_cell_results, halo_assembly_share_on_node, halo_free

  integer, parameter :: DEFAULT_TAG = 7100     !< message tag when none is given
  integer, parameter :: RESULT_TAG = 7300      !< tag of halo_gather_cell_results' messages

  !> A neighbour's assembly buffer in node-shared memory, up to the end of its part for us.
  type :: peer_buffer_t
    real(wp), pointer, contiguous :: values(:) => null()
    integer :: first = 1                         !< our first sum in it (send position)
  end type peer_buffer_t

  !> Neighbours, shared nodes, summation plans and buffers of one halo (read-only for users).
  type, public :: halo_t
    integer :: rank = 0                          !< this rank
    integer :: nnode_local = 0                   !< size(f, 2) expected
    integer :: ncomp_max = 0                     !< components the buffers hold per node
    integer :: tag = DEFAULT_TAG                 !< tag of halo_sum messages (tag+1: assembly)
    integer :: nneighbour = 0                    !< neighbour ranks
    integer, allocatable :: neighbour_rank(:)    !< (nneighbour) ascending
    integer, allocatable :: shared_start(:)      !< (nneighbour+1) offsets into shared_nodes
    integer, allocatable :: shared_nodes(:)      !< local nodes shared with each neighbour
    ! halo_sum plan: shared node sum_node(m) adds plan_source(plan_start(m):plan_start(m+1)-1)
    ! in that order; 0 = own value, s > 0 = received value for shared_nodes(s)
    integer :: nshared = 0                       !< distinct shared local nodes
    integer, allocatable :: sum_node(:)          !< (nshared) local node
    integer, allocatable :: plan_start(:)        !< (nshared+1) offsets into plan_source
    integer, allocatable :: plan_source(:)       !< sources in ascending rank order
    real(wp), allocatable :: send_buffer(:)      !< (ncomp_max * size(shared_nodes))
    real(wp), allocatable :: receive_buffer(:)   !< (ncomp_max * size(shared_nodes))
    type(comm_requests_t) :: requests            !< halo_sum transfers in flight
    integer :: sum_ncomp = 0                     !< components of the halo_sum in flight (0: none)
    ! order-fixed assembly (built from an explicit layout)
    logical :: has_assembly = .false.            !< assembly plan present
    integer :: ncell_local = 0                   !< size(cell_values, 3) expected
    integer :: slots = 0                         !< size(cell_values, 2) expected
    integer :: ntarget = 0                       !< size(f, 2) of the assembly: node columns,
                                                 !< then partial (per chunk) sums
    integer, allocatable :: source_target(:)     !< (slots*ncell_local) column of each
                                                 !< contribution (0: an unused slot)
    integer, allocatable :: send_start(:)        !< (nneighbour+1) offsets into send_source
    integer, allocatable :: send_source(:)       !< columns sent, per neighbour in order
    integer, allocatable :: receive_start(:)     !< (nneighbour+1) offsets of the received
    integer, allocatable :: combine_node(:)      !< nodes summed over their chunks: node m
    integer, allocatable :: combine_start(:)     !< adds combine_source(combine_start(m):
    integer, allocatable :: combine_source(:)    !< combine_start(m+1)-1) left to right: > 0 a
                                                 !< column, < 0 -(received position); the
                                                 !< first ncombine_local nodes have no
                                                 !< received source
    integer :: ncombine_local = 0                !< combined nodes of own chunks only
    integer :: nsent = 0                         !< sums sent (size(send_source))
    real(wp), pointer, contiguous :: assembly_buffer(:) => null()
                                                 !< (ncomp_max * (sent + received sums)) for
                                                 !< ncomp components: sum e at ncomp*(e-1)+1 :
                                                 !< ncomp*e, the sent ones first (e = send
                                                 !< position), the received after them (e =
                                                 !< nsent + receive position)
    type(comm_requests_t) :: assembly_requests   !< halo_assemble transfers in flight
    integer :: assembly_ncomp = 0                !< components of the assembly in flight
    real(wp) :: assembly_wait = 0.0_wp           !< wall time spent waiting for neighbours'
                                                 !< sums (s, summed over calls)
    ! pushed assembly (halo_assembly_push_nodes): the caller adds the contributions to the
    ! pushed columns itself; the rest is summed from the kept lists
    logical :: has_push = .false.                !< halo_assembly_push_nodes was called
    integer, allocatable :: kept_source(:)       !< contributions to columns not pushed,
    integer, allocatable :: kept_target(:)       !< ascending source, and their columns
    integer, allocatable :: kept_zero(:)         !< columns not pushed (zeroed before summing)
    ! assembly through node-shared memory (halo_assembly_share_on_node)
    logical :: on_node = .false.                 !< assembly_buffer is in `mailbox`
    type(comm_arena_t) :: mailbox                !< assembly_buffer and the send lists
    logical, allocatable :: direct(:)            !< (nneighbour) neighbour on this node: its
                                                 !< sums are read from its buffer
    integer :: ndirect = 0                       !< count(direct)
    type(peer_buffer_t), allocatable :: peer(:)  !< (nneighbour) the direct ones' buffers
    integer(i8) :: exchanges = 0                 !< assembly exchanges started
  end type halo_t

  !> Build a halo from a decomposition_t or an explicit_layout_t (the latter with the
  !> order-fixed assembly plan): call halo_build(halo, source, ncomp_max [, tag]).
  interface halo_build
    module procedure halo_build_decomposition, halo_build_layout
  end interface halo_build

contains

  !> Halo of a decomposition: nodal sums over the decomposition's local nodes.
  subroutine halo_build_decomposition(halo, decomp, ncomp_max, tag)
    type(halo_t), intent(out) :: halo              !< the halo
    type(decomposition_t), intent(in) :: decomp    !< this rank's decomposition
    integer, intent(in) :: ncomp_max               !< largest ncomp that will be exchanged
    integer, intent(in), optional :: tag           !< message tag (default 7100)
    call set_lists(halo, decomp%rank, decomp%nnode_local, decomp%neighbour_rank, &
                   decomp%shared_start, decomp%shared_nodes, ncomp_max, tag)
  end subroutine halo_build_decomposition

  !> Halo of an explicit layout: nodal sums and order-fixed assembly over its local nodes.
  subroutine halo_build_layout(halo, layout, ncomp_max, tag)
    type(halo_t), intent(out) :: halo              !< the halo
    type(explicit_layout_t), intent(in) :: layout  !< this rank's explicit layout
    integer, intent(in) :: ncomp_max               !< largest ncomp that will be exchanged
    integer, intent(in), optional :: tag           !< message tag (default 7100); uses tag+1 too
    call set_lists(halo, layout%rank, layout%nnode_local, layout%neighbour_rank, &
                   layout%shared_start, layout%shared_nodes, ncomp_max, tag)
    halo%has_assembly = .true.
    halo%ncell_local = layout%ncell_local
    halo%slots = layout%slots
    halo%ntarget = layout%ntarget
    halo%source_target = reshape(layout%cell_target, [layout%slots*layout%ncell_local])
    halo%send_start = layout%send_start
    halo%send_source = layout%send_source
    halo%receive_start = layout%receive_start
    call order_combine_plan(halo, layout%combine_node, layout%combine_start, &
                            layout%combine_source)
    halo%nsent = size(layout%send_source)
    allocate(halo%assembly_buffer(ncomp_max*(halo%nsent + layout%receive_start(layout% &
                                                                   nneighbour + 1) - 1)))
  end subroutine halo_build_layout

  !> The layout's combine plan with the nodes whose sums are all this rank's first (they are
  !> combined at halo_assemble_start, while the neighbours' sums are on their way), then those
  !> with received sums.
  subroutine order_combine_plan(halo, combine_node, combine_start, combine_source)
    type(halo_t), intent(inout) :: halo            !< halo being built
    integer, intent(in) :: combine_node(:)         !< the layout's combined nodes
    integer, intent(in) :: combine_start(:)        !< their offsets
    integer, intent(in) :: combine_source(:)       !< their sources
    logical :: local(size(combine_node))
    integer :: m, n, pass, next, nsource
    do m = 1, size(combine_node)
      local(m) = all(combine_source(combine_start(m):combine_start(m + 1) - 1) > 0)
    end do
    halo%ncombine_local = count(local)
    allocate(halo%combine_node(size(combine_node)), halo%combine_start(size(combine_node) + 1), &
             halo%combine_source(size(combine_source)))
    halo%combine_start(1) = 1
    n = 0
    do pass = 1, 2
      do m = 1, size(combine_node)
        if (local(m) .neqv. (pass == 1)) cycle
        n = n + 1
        nsource = combine_start(m + 1) - combine_start(m)
        next = halo%combine_start(n)
        halo%combine_node(n) = combine_node(m)
        halo%combine_start(n + 1) = next + nsource
        halo%combine_source(next:next + nsource - 1) = &
            combine_source(combine_start(m):combine_start(m + 1) - 1)
      end do
    end do
  end subroutine order_combine_plan

  !> Copy the neighbour lists, allocate the buffers and plan the ascending-rank sums.
  subroutine set_lists(halo, rank, nnode_local, neighbour_rank, shared_start, shared_nodes, &
                       ncomp_max, tag)
    type(halo_t), intent(inout) :: halo            !< halo being built
    integer, intent(in) :: rank                    !< this rank
    integer, intent(in) :: nnode_local             !< local nodes
    integer, intent(in) :: neighbour_rank(:)       !< neighbour ranks, ascending
    integer, intent(in) :: shared_start(:)         !< offsets per neighbour
    integer, intent(in) :: shared_nodes(:)         !< shared local nodes per neighbour
    integer, intent(in) :: ncomp_max               !< components per node in the buffers
    integer, intent(in), optional :: tag           !< message tag
    integer, allocatable :: count_of(:), slot_of(:), next(:)
    integer :: nneighbour, nlist, s, i, m, k, phase

    if (ncomp_max < 1) call fatal_local('halo_build: ncomp_max must be at least 1')
    halo%rank = rank
    halo%nnode_local = nnode_local
    halo%ncomp_max = ncomp_max
    if (present(tag)) halo%tag = tag
    nneighbour = size(neighbour_rank)
    halo%nneighbour = nneighbour
    halo%neighbour_rank = neighbour_rank
    halo%shared_start = shared_start(1:nneighbour + 1)
    nlist = shared_start(nneighbour + 1) - 1
    halo%shared_nodes = shared_nodes(1:nlist)
    allocate(halo%direct(nneighbour))
    halo%direct = .false.
    allocate(halo%send_buffer(ncomp_max*nlist), halo%receive_buffer(ncomp_max*nlist))

    ! shared nodes and the number of ranks holding each (1 + neighbours listing it)
    allocate(count_of(nnode_local), slot_of(nnode_local))
    count_of = 0
    do s = 1, nlist
      count_of(halo%shared_nodes(s)) = count_of(halo%shared_nodes(s)) + 1
    end do
    halo%nshared = count(count_of > 0)
    allocate(halo%sum_node(halo%nshared), halo%plan_start(halo%nshared + 1))
    slot_of = 0
    halo%plan_start(1) = 1
    m = 0
    do i = 1, nnode_local
      if (count_of(i) == 0) cycle
      m = m + 1
      slot_of(i) = m
      halo%sum_node(m) = i
      halo%plan_start(m + 1) = halo%plan_start(m) + count_of(i) + 1
    end do
    ! sources in ascending rank order: lower neighbours, this rank, higher neighbours
    allocate(halo%plan_source(halo%plan_start(halo%nshared + 1) - 1), next(halo%nshared))
    next = halo%plan_start(1:halo%nshared)
    do phase = 1, 3
      if (phase == 2) then
        do m = 1, halo%nshared
          halo%plan_source(next(m)) = 0
          next(m) = next(m) + 1
        end do
        cycle
      end if
      do k = 1, nneighbour
        if ((phase == 1) .neqv. (neighbour_rank(k) < rank)) cycle
        do s = halo%shared_start(k), halo%shared_start(k + 1) - 1
          m = slot_of(halo%shared_nodes(s))
          halo%plan_source(next(m)) = s
          next(m) = next(m) + 1
        end do
      end do
    end do
  end subroutine set_lists

  !> Sum nodal partials over all ranks at shared nodes (start + finish).
  subroutine halo_sum(halo, f)
    type(halo_t), intent(inout) :: halo            !< the halo
    real(wp), intent(inout) :: f(:,:)              !< (ncomp, nnode_local) partials -> sums
    call halo_sum_start(halo, f)
    call halo_sum_finish(halo, f)
  end subroutine halo_sum

  !> Post the receives, pack this rank's partials at shared nodes and post the sends.
  subroutine halo_sum_start(halo, f)
    type(halo_t), intent(inout), asynchronous :: halo !< the halo (buffers in use until finish)
    real(wp), intent(in) :: f(:,:)                 !< (ncomp, nnode_local) this rank's partials
    integer :: ncomp, k, s, first, last

    ncomp = size(f, 1)
    call check_nodal(halo, f, 'halo_sum_start')
    if (halo%sum_ncomp /= 0) call fatal_local('halo_sum_start: previous exchange not finished')
    halo%sum_ncomp = ncomp
    do k = 1, halo%nneighbour
      first = ncomp*(halo%shared_start(k) - 1) + 1
      last = ncomp*(halo%shared_start(k + 1) - 1)
      call comm_irecv_real(halo%receive_buffer(first:last), halo%neighbour_rank(k), halo%tag, &
                           halo%requests)
    end do
    do k = 1, halo%nneighbour
      do s = halo%shared_start(k), halo%shared_start(k + 1) - 1
        halo%send_buffer(ncomp*(s - 1) + 1:ncomp*s) = f(:, halo%shared_nodes(s))
      end do
      first = ncomp*(halo%shared_start(k) - 1) + 1
      last = ncomp*(halo%shared_start(k + 1) - 1)
      call comm_isend_real(halo%send_buffer(first:last), halo%neighbour_rank(k), halo%tag, &
                           halo%requests)
    end do
  end subroutine halo_sum_start

  !> Wait for the neighbours' partials and add them at shared nodes in ascending rank order.
  subroutine halo_sum_finish(halo, f)
    type(halo_t), intent(inout), asynchronous :: halo !< the halo
    real(wp), intent(inout) :: f(:,:)              !< (ncomp, nnode_local) partials -> sums
    real(wp) :: total(size(f, 1))
    integer :: ncomp, m, p, s

    ncomp = size(f, 1)
    if (halo%sum_ncomp /= ncomp) call fatal_local('halo_sum_finish: no matching halo_sum_start')
    call check_nodal(halo, f, 'halo_sum_finish')
    call comm_waitall(halo%requests)
    halo%sum_ncomp = 0
    do m = 1, halo%nshared
      do p = halo%plan_start(m), halo%plan_start(m + 1) - 1
        s = halo%plan_source(p)
        if (p == halo%plan_start(m)) then
          total = source_value(s)
        else
          total = total + source_value(s)
        end if
      end do
      f(:, halo%sum_node(m)) = total
    end do

  contains

    !> Value of a source: own partial (0) or received partial for shared_nodes(s).
    function source_value(s) result(v)
      integer, intent(in) :: s          !< plan source
      real(wp) :: v(ncomp)
      if (s == 0) then
        v = f(:, halo%sum_node(m))
      else
        v = halo%receive_buffer(ncomp*(s - 1) + 1:ncomp*s)
      end if
    end function source_value

  end subroutine halo_sum_finish

  !> Order-fixed assembly of cell contributions into nodal sums (start + finish).
  subroutine halo_assemble(halo, cell_values, f)
    type(halo_t), intent(inout) :: halo            !< halo built from an explicit layout
    real(wp), intent(in) :: cell_values(:,:,:)     !< (ncomp, slots, ncell_local) contributions
    real(wp), intent(out) :: f(:,:)                !< (ncomp, ntarget) nodal sums (node columns)
    call halo_assemble_start(halo, cell_values, f)
    call halo_assemble_finish(halo, f)
  end subroutine halo_assemble

  !> Sum this rank's contributions into their columns of f (every column, or with pushed =
  !> .true. after halo_assembly_push_nodes only those the caller did not push: f holds the
  !> pushed ones' sums already), then post the receives and send the neighbours their sums.
  subroutine halo_assemble_start(halo, cell_values, f, pushed)
    type(halo_t), intent(inout), asynchronous :: halo !< halo built from an explicit layout
    real(wp), intent(in) :: cell_values(:,:,:)     !< (ncomp, slots, ncell_local), all final
    real(wp), intent(inout) :: f(:,:)              !< (ncomp, ntarget) sums of own chunks
    logical, intent(in), optional :: pushed        !< the pushed columns are summed in f already
    integer :: ncomp
    logical :: use_push

    ncomp = size(cell_values, 1)
    call check_cells(halo, cell_values, f, 'halo_assemble_start')
    if (halo%assembly_ncomp /= 0) &
      call fatal_local('halo_assemble_start: previous exchange not finished')
    halo%assembly_ncomp = ncomp
    use_push = .false.
    if (present(pushed)) use_push = pushed
    if (use_push) then
      if (.not. halo%has_push) call fatal_local('halo_assemble_start: pushed = .true. '// &
                                                'without halo_assembly_push_nodes')
      call sum_kept_in_plan_order(halo, ncomp, size(cell_values, 2)*size(cell_values, 3), &
                                  cell_values, f)
    else
      call sum_in_plan_order(halo, ncomp, size(cell_values, 2)*size(cell_values, 3), &
                             cell_values, f)
    end if
    call start_exchange(halo, ncomp, f)
  end subroutine halo_assemble_start

  !> halo_assemble for a caller that has summed this rank's contributions into every column of
  !> f itself (zero, then each contribution added to its column source_target(j + slots (l-1))
  !> in ascending local cell order, the plan's order): the exchange and the sums over the
  !> chunks only. The same bits as halo_assemble of the same contributions.
  subroutine halo_assemble_summed(halo, f)
    type(halo_t), intent(inout), asynchronous :: halo !< halo built from an explicit layout
    real(wp), intent(inout) :: f(:,:)              !< (ncomp, ntarget) in: own chunks' sums;
                                                   !< out: nodal sums
    if (.not. halo%has_assembly) call fatal_local('halo_assemble_summed: the halo was not '// &
                                                  'built from an explicit layout')
    if (size(f, 2) /= halo%ntarget .or. size(f, 1) > halo%ncomp_max) &
      call fatal_local('halo_assemble_summed: f does not fit the halo')
    if (halo%assembly_ncomp /= 0) &
      call fatal_local('halo_assemble_summed: previous exchange not finished')
    halo%assembly_ncomp = size(f, 1)
    call start_exchange(halo, size(f, 1), f)
    call halo_assemble_finish(halo, f)
  end subroutine halo_assemble_summed

  !> The exchange of halo_assemble_start once this rank's chunk sums are in f: post the
  !> receives, send the neighbours their sums, combine the nodes of own chunks only.
  subroutine start_exchange(halo, ncomp, f)
    type(halo_t), intent(inout), asynchronous :: halo !< halo built from an explicit layout
    integer, intent(in) :: ncomp                   !< components per sum
    real(wp), intent(inout) :: f(:,:)              !< (ncomp, ntarget) sums of own chunks
    integer :: k, first, last
    ! the neighbours of this node have read the last exchange before any of the buffer is
    ! written again, by this rank or by a message (with another number of components the
    ! parts lie elsewhere: a receive may land where they were reading)
    if (halo%on_node) then
      halo%exchanges = halo%exchanges + 1
      call comm_mail_wait_read(halo%mailbox, halo%ndirect*(halo%exchanges - 1))
    end if
    do k = 1, halo%nneighbour
      if (halo%direct(k)) cycle
      first = ncomp*(halo%nsent + halo%receive_start(k) - 1) + 1
      last = ncomp*(halo%nsent + halo%receive_start(k + 1) - 1)
      call comm_irecv_real(halo%assembly_buffer(first:last), halo%neighbour_rank(k), &
                           halo%tag + 1, halo%assembly_requests)
    end do
    do k = 1, halo%nneighbour
      call pack_sums(halo, k, ncomp, f)
      if (halo%direct(k)) cycle
      first = ncomp*(halo%send_start(k) - 1) + 1
      last = ncomp*(halo%send_start(k + 1) - 1)
      call comm_isend_real(halo%assembly_buffer(first:last), halo%neighbour_rank(k), &
                           halo%tag + 1, halo%assembly_requests)
    end do
    if (halo%on_node) call comm_mail_post(halo%mailbox, halo%exchanges)
    call combine_chunks(halo, ncomp, 1, halo%ncombine_local, f)
  end subroutine start_exchange

  !> Wait for the neighbours' sums and add, at every node with some of them, the chunks' sums
  !> in ascending chunk order into its column (the nodes of own chunks only were combined by
  !> halo_assemble_start).
  subroutine halo_assemble_finish(halo, f)
    type(halo_t), intent(inout), asynchronous :: halo !< halo built from an explicit layout
    real(wp), intent(inout) :: f(:,:)              !< (ncomp, ntarget) nodal sums
    real(wp) :: clock
    integer :: ncomp

    ncomp = size(f, 1)
    if (halo%assembly_ncomp /= ncomp) &
      call fatal_local('halo_assemble_finish: no matching halo_assemble_start')
    if (size(f, 2) /= halo%ntarget) call fatal_local('halo_assemble_finish: f does not have '// &
                                                     'the layout''s columns')
    if (halo%on_node) call take_from_node(halo, ncomp)
    clock = comm_wtime()
    call comm_waitall(halo%assembly_requests)
    halo%assembly_wait = halo%assembly_wait + (comm_wtime() - clock)
    halo%assembly_ncomp = 0
    call combine_chunks(halo, ncomp, halo%ncombine_local + 1, size(halo%combine_node), f)
  end subroutine halo_assemble_finish

  !> The sums of the neighbours on this node: copied from their buffers into the
  !> received part of assembly_buffer once they have posted this exchange, as a message
  !> would have put them (the wait counts in assembly_wait, the copy does not).
  subroutine take_from_node(halo, ncomp)
    type(halo_t), intent(inout) :: halo            !< halo sharing its buffer on the node
    integer, intent(in) :: ncomp                   !< components of this exchange
    integer :: k, first, n, at, e
    real(wp) :: clock
    do k = 1, halo%nneighbour
      if (.not. halo%direct(k)) cycle
      clock = comm_wtime()
      call comm_mail_wait_posted(halo%mailbox, halo%neighbour_rank(k), halo%exchanges)
      halo%assembly_wait = halo%assembly_wait + (comm_wtime() - clock)
      first = ncomp*(halo%peer(k)%first - 1)
      at = ncomp*(halo%nsent + halo%receive_start(k) - 1)
      n = ncomp*(halo%receive_start(k + 1) - halo%receive_start(k))
      do e = 1, n
        halo%assembly_buffer(at + e) = halo%peer(k)%values(first + e)
      end do
      call comm_mail_read(halo%mailbox, halo%neighbour_rank(k))
    end do
  end subroutine take_from_node

  !> Move the assembly's buffer into node-shared memory, so that the neighbours on this node
  !> exchange their sums without messages (collective over all ranks; after halo_build
  !> from a layout, before any exchange). Each rank publishes its buffer and send lists; each
  !> finds its part in every neighbour's buffer on the node (the neighbour's send list for it
  !> must hold as many sums as this rank's receive list from it). `messages_with`
  !> keeps messages with some ranks of the node (tests of a mix of both ways, as between
  !> nodes; both sides of a pair must name each other).
  subroutine halo_assembly_share_on_node(halo, messages_with)
    type(halo_t), intent(inout) :: halo            !< halo built from an explicit layout
    integer, intent(in), optional :: messages_with(:) !< world ranks to exchange messages with
    integer, parameter :: REAL_BYTES = storage_size(1.0_wp)/8, INT_BYTES = storage_size(1)/8
    integer, pointer, contiguous :: info(:), peer_info(:)
    real(wp), pointer, contiguous :: shared(:)
    integer :: nbuffer, ninfo, nn, k, j, peer_nn, first, nsum
    if (.not. halo%has_assembly) call fatal_local('halo_assembly_share_on_node: the halo was '// &
                                                  'not built from an explicit layout')
    if (halo%assembly_ncomp /= 0 .or. halo%on_node) call fatal_local( &
      'halo_assembly_share_on_node: call it once, with no exchange in flight')
    nn = halo%nneighbour
    nbuffer = size(halo%assembly_buffer)
    ! the lists the neighbours read: ncomp_max, nneighbour, neighbour_rank, send_start
    ninfo = 2 + nn + (nn + 1)
    call comm_arena_create(halo%mailbox, [int(nbuffer, i8)*REAL_BYTES, int(ninfo, i8)*INT_BYTES])
    call c_f_pointer(comm_arena_array(halo%mailbox, 1), shared, [nbuffer])
    call c_f_pointer(comm_arena_array(halo%mailbox, 2), info, [ninfo])
    info = [halo%ncomp_max, nn, halo%neighbour_rank, halo%send_start]
    deallocate(halo%assembly_buffer)
    halo%assembly_buffer => shared
    halo%on_node = .true.
    call comm_arena_sync(halo%mailbox)
    call comm_barrier()                            ! every rank's lists written
    call comm_arena_sync(halo%mailbox)
    allocate(halo%peer(nn))
    do k = 1, nn
      halo%direct(k) = comm_arena_on_node(halo%mailbox, halo%neighbour_rank(k))
      if (present(messages_with)) then
        if (any(messages_with == halo%neighbour_rank(k))) halo%direct(k) = .false.
      end if
      if (.not. halo%direct(k)) cycle
      call c_f_pointer(comm_arena_peer_array(halo%mailbox, halo%neighbour_rank(k), 2), &
                       peer_info, [2])
      peer_nn = peer_info(2)
      if (peer_info(1) /= halo%ncomp_max) call fatal_local('halo_assembly_share_on_node: '// &
          'the neighbours'' halos hold different numbers of components')
      call c_f_pointer(comm_arena_peer_array(halo%mailbox, halo%neighbour_rank(k), 2), &
                       peer_info, [2 + peer_nn + peer_nn + 1])
      j = findloc(peer_info(3:2 + peer_nn), halo%rank, dim=1)
      if (j == 0) call fatal_local('halo_assembly_share_on_node: a neighbour does not list '// &
                                   'this rank')
      first = peer_info(2 + peer_nn + j)
      nsum = peer_info(2 + peer_nn + j + 1) - first
      if (nsum /= halo%receive_start(k + 1) - halo%receive_start(k)) call fatal_local( &
        'halo_assembly_share_on_node: a neighbour sends a different number of sums')
      call c_f_pointer(comm_arena_peer_array(halo%mailbox, halo%neighbour_rank(k), 1), &
                       halo%peer(k)%values, [halo%ncomp_max*(first - 1 + nsum)])
      halo%peer(k)%first = first
    end do
    halo%ndirect = count(halo%direct)
  end subroutine halo_assembly_share_on_node

  !> Release a halo's buffers (collective over all ranks if it was shared on the node).
  subroutine halo_free(halo)
    type(halo_t), intent(inout) :: halo            !< the halo
    if (halo%on_node) then
      nullify(halo%assembly_buffer)
      call comm_arena_free(halo%mailbox)
      halo%on_node = .false.
      halo%direct = .false.
      halo%ndirect = 0
    else if (associated(halo%assembly_buffer)) then
      deallocate(halo%assembly_buffer)
    end if
  end subroutine halo_free

  !> Let the caller assemble the columns marked in `pushed` itself: it adds each contribution
  !> to such a column straight into the nodal array, in ascending global cell order, starting
  !> from zero (the same bits as the plan), and halo_assemble_start(..., pushed=.true.) sums
  !> only the other columns.
  subroutine halo_assembly_push_nodes(halo, pushed)
    type(halo_t), intent(inout) :: halo            !< halo built from an explicit layout
    logical, intent(in) :: pushed(:)               !< (ntarget) columns the caller assembles
    integer :: source, i, nkept, pass
    if (.not. halo%has_assembly) call fatal_local('halo_assembly_push_nodes: the halo was '// &
                                                  'not built from an explicit layout')
    if (size(pushed) /= halo%ntarget) call fatal_local('halo_assembly_push_nodes: '// &
                                                       'pushed does not fit the halo')
    do pass = 1, 2
      if (pass == 2) allocate(halo%kept_source(nkept), halo%kept_target(nkept))
      nkept = 0
      do source = 1, size(halo%source_target)
        i = halo%source_target(source)
        if (i == 0) cycle
        if (pushed(i)) cycle
        nkept = nkept + 1
        if (pass == 1) cycle
        halo%kept_source(nkept) = source
        halo%kept_target(nkept) = i
      end do
    end do
    halo%kept_zero = pack([(i, i = 1, halo%ntarget)], .not. pushed)
    halo%has_push = .true.
  end subroutine halo_assembly_push_nodes

  !> This rank's chunk sums, each in ascending global cell order (the order fixes the bits;
  !> zero without contributions): one pass over the cell array in ascending order
  !> (values(:, source), source = j + slots*(l-1) the column of slot j of cell l: streamed, the
  !> nodal array is the one accessed at random). 0 + x = x, so starting from zero gives the
  !> same bits as starting from the first contribution (up to the sign of a zero sum).
  subroutine sum_in_plan_order(halo, ncomp, nsource, values, f)
    type(halo_t), intent(in) :: halo               !< halo with its assembly plan
    integer, intent(in) :: ncomp                   !< components per contribution
    integer, intent(in) :: nsource                 !< slots x local cells
    real(wp), intent(in) :: values(ncomp, nsource) !< cell contributions, one per column
    real(wp), intent(inout) :: f(:,:)              !< (ncomp, ntarget) sums
    integer :: i, source
    if (ncomp == 3) then
      do i = 1, size(f, 2)                        ! (not f = 0: one memset call per node)
        f(1, i) = 0.0_wp
        f(2, i) = 0.0_wp
        f(3, i) = 0.0_wp
      end do
      do source = 1, nsource
        i = halo%source_target(source)
        if (i == 0) cycle
        f(1, i) = f(1, i) + values(1, source)
        f(2, i) = f(2, i) + values(2, source)
        f(3, i) = f(3, i) + values(3, source)
      end do
    else if (ncomp == 1) then
      do i = 1, size(f, 2)
        f(1, i) = 0.0_wp
      end do
      do source = 1, nsource
        i = halo%source_target(source)
        if (i == 0) cycle
        f(1, i) = f(1, i) + values(1, source)
      end do
    else
      f(1:ncomp, :) = 0.0_wp
      do source = 1, nsource
        i = halo%source_target(source)
        if (i == 0) cycle
        f(1:ncomp, i) = f(1:ncomp, i) + values(:, source)
      end do
    end if
  end subroutine sum_in_plan_order

  !> sum_in_plan_order for the pushed assembly: only the kept columns are zeroed and summed
  !> (the pushed ones hold their sums already).
  subroutine sum_kept_in_plan_order(halo, ncomp, nsource, values, f)
    type(halo_t), intent(in) :: halo               !< halo with its assembly plan
    integer, intent(in) :: ncomp                   !< components per contribution
    integer, intent(in) :: nsource                 !< slots x local cells
    real(wp), intent(in) :: values(ncomp, nsource) !< cell contributions, one per column
    real(wp), intent(inout) :: f(:,:)              !< (ncomp, ntarget) sums
    integer :: k, i, source
    do k = 1, size(halo%kept_zero)
      f(1:ncomp, halo%kept_zero(k)) = 0.0_wp
    end do
    if (ncomp == 3) then                          ! (the forces: written out, no slices)
      do k = 1, size(halo%kept_source)
        i = halo%kept_target(k)
        source = halo%kept_source(k)
        f(1, i) = f(1, i) + values(1, source)
        f(2, i) = f(2, i) + values(2, source)
        f(3, i) = f(3, i) + values(3, source)
      end do
    else
      do k = 1, size(halo%kept_source)
        i = halo%kept_target(k)
        f(1:ncomp, i) = f(1:ncomp, i) + values(:, halo%kept_source(k))
      end do
    end if
  end subroutine sum_kept_in_plan_order

  !> Combined nodes first..last (touched by several chunks, or only by other ranks' chunks):
  !> their chunks' sums, own columns and received values, added left to right in ascending
  !> chunk order.
  subroutine combine_chunks(halo, ncomp, first, last, f)
    type(halo_t), intent(in) :: halo               !< halo (after the exchange if received
                                                   !< sums are read)
    integer, intent(in) :: ncomp                   !< components per sum
    integer, intent(in) :: first, last             !< range of combined nodes
    real(wp), intent(inout) :: f(:,:)              !< (ncomp, ntarget) sums
    real(wp) :: total(ncomp)
    integer :: m, p, source, offset
    do m = first, last
      do p = halo%combine_start(m), halo%combine_start(m + 1) - 1
        source = halo%combine_source(p)
        if (source > 0) then
          if (p == halo%combine_start(m)) then
            total = f(1:ncomp, source)
          else
            total = total + f(1:ncomp, source)
          end if
        else
          offset = ncomp*(halo%nsent - source - 1)
          if (p == halo%combine_start(m)) then
            total = halo%assembly_buffer(offset + 1:offset + ncomp)
          else
            total = total + halo%assembly_buffer(offset + 1:offset + ncomp)
          end if
        end if
      end do
      f(1:ncomp, halo%combine_node(m)) = total
    end do
  end subroutine combine_chunks

  !> The sums neighbour k needs, packed into the sent part of assembly_buffer (columns as
  !> above).
  subroutine pack_sums(halo, k, ncomp, f)
    type(halo_t), intent(inout) :: halo            !< halo with its assembly plan
    integer, intent(in) :: k                       !< neighbour
    integer, intent(in) :: ncomp                   !< components per sum
    real(wp), intent(in) :: f(:,:)                 !< (ncomp, ntarget) sums
    integer :: t
    do t = halo%send_start(k), halo%send_start(k + 1) - 1
      halo%assembly_buffer(ncomp*(t - 1) + 1:ncomp*t) = f(1:ncomp, halo%send_source(t))
    end do
  end subroutine pack_sums

  !> Stop with a message if a nodal array does not fit the halo.
  subroutine check_nodal(halo, f, where)
    type(halo_t), intent(in) :: halo               !< the halo
    real(wp), intent(in) :: f(:,:)                 !< nodal array
    character(len=*), intent(in) :: where          !< calling routine
    character(len=160) :: text
    if (size(f, 2) /= halo%nnode_local .or. size(f, 1) > halo%ncomp_max .or. size(f, 1) < 1) then
      write(text, '(a,i0,a,i0,a,i0,a,i0,a)') where//': f is (', size(f, 1), ', ', size(f, 2), &
          '), the halo takes (1..', halo%ncomp_max, ', ', halo%nnode_local, ')'
      call fatal_local(text)
    end if
  end subroutine check_nodal

  !> Stop with a message if a cell array or the nodal sums do not fit the halo's assembly plan.
  subroutine check_cells(halo, cell_values, f, where)
    type(halo_t), intent(in) :: halo               !< the halo
    real(wp), intent(in) :: cell_values(:,:,:)     !< cell contributions
    real(wp), intent(in) :: f(:,:)                 !< nodal sums
    character(len=*), intent(in) :: where          !< calling routine
    character(len=200) :: text
    if (.not. halo%has_assembly) call fatal_local(where//': the halo was not built from an '// &
        'explicit layout')
    if (size(cell_values, 1) > halo%ncomp_max .or. size(cell_values, 1) < 1 .or. &
        size(cell_values, 2) /= halo%slots .or. size(cell_values, 3) /= halo%ncell_local) then
      write(text, '(a,3(i0,a),3(i0,a))') where//': cell_values is (', size(cell_values, 1), &
          ', ', size(cell_values, 2), ', ', size(cell_values, 3), '), the halo takes (1..', &
          halo%ncomp_max, ', ', halo%slots, ', ', halo%ncell_local, ')'
      call fatal_local(text)
    end if
    if (size(f, 1) /= size(cell_values, 1) .or. size(f, 2) /= halo%ntarget) then
      write(text, '(a,4(i0,a))') where//': f is (', size(f, 1), ', ', size(f, 2), &
          '), the assembly needs (', size(cell_values, 1), ', ', halo%ntarget, ')'
      call fatal_local(text)
    end if
  end subroutine check_cells

  !> The results of the cells this rank's output piece reads (layout%result_cell, ascending)
  !> from every rank's results of the cells it computes: this rank's own are copied, the
  !> others' sent by the ranks that compute them (the layout's output plan). Collective over
  !> the ranks that exchange results.
  subroutine halo_gather_cell_results(layout, local_values, values)
    type(explicit_layout_t), intent(in) :: layout            !< this rank's layout
    real(wp), intent(in) :: local_values(:,:)                !< (ncomp, ncell_local) results
    real(wp), allocatable, intent(out) :: values(:,:)        !< (ncomp, size(result_cell))
    real(wp), allocatable, asynchronous :: send(:), receive(:)
    type(comm_requests_t) :: requests
    integer :: ncomp, r, first, last, k, source
    ncomp = size(local_values, 1)
    allocate(send(ncomp*layout%result_send_start(layout%nranks)), &
             receive(ncomp*layout%result_receive_start(layout%nranks)))
    do r = 0, layout%nranks - 1
      first = layout%result_receive_start(r)
      last = layout%result_receive_start(r + 1)
      if (last > first) call comm_irecv_real(receive(ncomp*first + 1:ncomp*last), r, &
                                             RESULT_TAG, requests)
    end do
    do r = 0, layout%nranks - 1
      first = layout%result_send_start(r)
      last = layout%result_send_start(r + 1)
      if (last == first) cycle
      do k = first + 1, last
        send(ncomp*(k - 1) + 1:ncomp*k) = local_values(:, layout%result_send_cell(k))
      end do
      call comm_isend_real(send(ncomp*first + 1:ncomp*last), r, RESULT_TAG, requests)
    end do
    call comm_waitall(requests)
    allocate(values(ncomp, size(layout%result_cell)))
    do k = 1, size(layout%result_cell)
      source = layout%result_source(k)
      if (source > 0) then
        values(:, k) = local_values(:, source)
      else
        values(:, k) = receive(ncomp*(-source - 1) + 1:ncomp*(-source))
      end if
    end do
  end subroutine halo_gather_cell_results

end module mefem_halo
