!> METIS element partitioning and per-rank decomposition on structured tet and triangle meshes.
! ranks: 1
program test_partition
  use mefem_kinds, only: wp
  use mefem_errors, only: status_t
  use mefem_output_mesh, only: output_mesh_t, TOPO_TET4, TOPO_TRI3
  use mefem_metis, only: metis_partition_elements
  use mefem_decomposition, only: decomposition_t, build_decomposition, fill_output_mesh
  use mefem_testing, only: test_start, test_finish, check
  implicit none

  integer, allocatable :: elem_start(:), elem_nodes(:)
  real(wp), allocatable :: x(:,:)
  integer :: nelem, nnode, nparts

  call test_start('partition')

  ! 6x6x6 cubes, 6 tetrahedra each: 1296 elements, 343 nodes; face neighbours share 3 nodes.
  call make_tet_mesh(6, nelem, nnode, elem_start, elem_nodes, x)
  do nparts = 1, 4
    call check_partition('tet', nelem, nnode, elem_start, elem_nodes, x, 3, TOPO_TET4, nparts)
  end do
  call check_weighted(nelem, nnode, elem_start, elem_nodes, x)

  ! 12x12 squares, 2 triangles each, plus one node no element touches.
  call make_tri_mesh(12, nelem, nnode, elem_start, elem_nodes, x)
  do nparts = 1, 4
    call check_partition('tri', nelem, nnode, elem_start, elem_nodes, x, 2, TOPO_TRI3, nparts)
  end do

  call check_errors(nelem, nnode, elem_start, elem_nodes)
  call test_finish()

contains

  !> Structured cube [0,1]^3 of n^3 cubes, each split into 6 tetrahedra around its diagonal.
  subroutine make_tet_mesh(n, nelem, nnode, elem_start, elem_nodes, x)
    integer, intent(in) :: n                              !< cubes per side
    integer, intent(out) :: nelem, nnode                  !< mesh sizes
    integer, allocatable, intent(out) :: elem_start(:), elem_nodes(:) !< connectivity
    real(wp), allocatable, intent(out) :: x(:,:)          !< (3,nnode) coordinates
    integer, parameter :: paths(3, 6) = reshape([1, 2, 3, 1, 3, 2, 2, 1, 3, 2, 3, 1, &
                                                 3, 1, 2, 3, 2, 1], [3, 6])
    integer :: i, j, k, t, s, e, corner(3)
    nnode = (n + 1)**3
    nelem = 6*n**3
    allocate(x(3, nnode), elem_start(nelem + 1), elem_nodes(4*nelem))
    do k = 0, n
      do j = 0, n
        do i = 0, n
          x(:, lattice_node(n, i, j, k)) = [real(i, wp), real(j, wp), real(k, wp)]/real(n, wp)
        end do
      end do
    end do
    e = 0
    do k = 0, n - 1
      do j = 0, n - 1
        do i = 0, n - 1
          do t = 1, 6
            e = e + 1
            elem_start(e) = 4*(e - 1) + 1
            corner = [i, j, k]
            elem_nodes(elem_start(e)) = lattice_node(n, corner(1), corner(2), corner(3))
            do s = 1, 3
              corner(paths(s, t)) = corner(paths(s, t)) + 1
              elem_nodes(elem_start(e) + s) = lattice_node(n, corner(1), corner(2), corner(3))
            end do
          end do
        end do
      end do
    end do
    elem_start(nelem + 1) = 4*nelem + 1
  end subroutine make_tet_mesh

  !> Node number of lattice point (i,j,k) of an n^3-cube mesh.
  pure integer function lattice_node(n, i, j, k)
    integer, intent(in) :: n          !< cubes per side
    integer, intent(in) :: i, j, k    !< lattice position, 0..n
    lattice_node = 1 + i + (n + 1)*(j + (n + 1)*k)
  end function lattice_node

  !> Unit square of n^2 squares split into 2 triangles each, plus one isolated last node.
  subroutine make_tri_mesh(n, nelem, nnode, elem_start, elem_nodes, x)
    integer, intent(in) :: n                              !< squares per side
    integer, intent(out) :: nelem, nnode                  !< mesh sizes
    integer, allocatable, intent(out) :: elem_start(:), elem_nodes(:) !< connectivity
    real(wp), allocatable, intent(out) :: x(:,:)          !< (3,nnode) coordinates
    integer :: i, j, e, a, b, c, d
    nnode = (n + 1)**2 + 1
    nelem = 2*n**2
    allocate(x(3, nnode), elem_start(nelem + 1), elem_nodes(3*nelem))
    do j = 0, n
      do i = 0, n
        x(:, 1 + i + (n + 1)*j) = [real(i, wp)/n, real(j, wp)/n, 0.0_wp]
      end do
    end do
    x(:, nnode) = [2.0_wp, 2.0_wp, 0.0_wp]
    e = 0
    do j = 0, n - 1
      do i = 0, n - 1
        a = 1 + i + (n + 1)*j
        b = a + 1
        c = b + n + 1
        d = a + n + 1
        elem_nodes(3*e + 1:3*e + 6) = [a, b, c, a, c, d]
        elem_start(e + 1:e + 2) = [3*e + 1, 3*e + 4]
        e = e + 2
      end do
    end do
    elem_start(nelem + 1) = 3*nelem + 1
  end subroutine make_tri_mesh

  !> Partition into nparts, then check the partition and every rank's decomposition.
  subroutine check_partition(mesh, nelem, nnode, elem_start, elem_nodes, x, ncommon, topo, &
                             nparts)
    character(len=*), intent(in) :: mesh                  !< mesh name for messages
    integer, intent(in) :: nelem, nnode                   !< mesh sizes
    integer, intent(in) :: elem_start(:), elem_nodes(:)   !< connectivity
    real(wp), intent(in) :: x(:,:)                        !< coordinates
    integer, intent(in) :: ncommon, topo, nparts          !< dual-graph rule, topology, parts
    integer :: elem_part(nelem), again(nelem), part_count(0:nparts - 1)
    type(decomposition_t) :: decomp(0:nparts - 1)
    type(status_t) :: status
    character(len=40) :: tag
    integer :: e, r
    logical :: ok

    write(tag, '(a,a,i0,a)') mesh, ' nparts=', nparts, ':'
    call metis_partition_elements(nelem, nnode, elem_start, elem_nodes, ncommon, nparts, &
                                  elem_part=elem_part, status=status)
    call check(status%ok, trim(tag)//' METIS succeeds')
    if (.not. status%ok) return
    call metis_partition_elements(nelem, nnode, elem_start, elem_nodes, ncommon, nparts, &
                                  elem_part=again, status=status)
    call check(status%ok .and. all(again == elem_part), trim(tag)//' deterministic')
    call check(all(elem_part >= 0 .and. elem_part < nparts), trim(tag)//' parts in range')
    if (.not. all(elem_part >= 0 .and. elem_part < nparts)) return
    part_count = 0
    do e = 1, nelem
      part_count(elem_part(e)) = part_count(elem_part(e)) + 1
    end do
    call check(all(part_count > 0), trim(tag)//' no empty part')
    call check(maxval(part_count) <= 1.1_wp*real(nelem, wp)/nparts + 1.0_wp, &
               trim(tag)//' balanced (max <= 1.1 average + 1)')

    do r = 0, nparts - 1
      call build_decomposition(r, nparts, nelem, nnode, elem_start, elem_nodes, elem_part, &
                               decomp(r), status)
      ok = status%ok
      if (.not. ok) exit
    end do
    call check(ok, trim(tag)//' decompositions built')
    if (.not. ok) return
    call check_elements(tag, nelem, elem_start, elem_nodes, elem_part, decomp)
    call check_nodes(tag, nnode, elem_start, elem_nodes, elem_part, decomp)
    call check_output(tag, nnode, nelem, x, topo, decomp)
  end subroutine check_partition

  !> Elements: each in exactly one rank, ascending, and local connectivity maps back.
  subroutine check_elements(tag, nelem, elem_start, elem_nodes, elem_part, decomp)
    character(len=*), intent(in) :: tag                   !< message prefix
    integer, intent(in) :: nelem                          !< elements
    integer, intent(in) :: elem_start(:), elem_nodes(:)   !< global connectivity
    integer, intent(in) :: elem_part(:)                   !< partition
    type(decomposition_t), intent(in) :: decomp(0:)       !< all ranks
    integer :: seen(nelem), r, i, e, n, k
    logical :: ok_part, ok_conn
    seen = 0
    ok_part = .true.
    ok_conn = .true.
    do r = 0, size(decomp) - 1
      associate(d => decomp(r))
        n = d%nelem_local
        ok_part = ok_part .and. size(d%elem_global) == n
        if (n > 1) ok_part = ok_part .and. all(d%elem_global(2:n) > d%elem_global(1:n - 1))
        do i = 1, n
          e = d%elem_global(i)
          seen(e) = seen(e) + 1
          ok_part = ok_part .and. elem_part(e) == r
          k = elem_start(e + 1) - elem_start(e)
          ok_conn = ok_conn .and. d%elem_start_local(i + 1) - d%elem_start_local(i) == k
          if (ok_conn) ok_conn = all(d%node_global(d%elem_nodes_local( &
              d%elem_start_local(i):d%elem_start_local(i + 1) - 1)) == &
              elem_nodes(elem_start(e):elem_start(e + 1) - 1))
        end do
      end associate
    end do
    call check(all(seen == 1), trim(tag)//' every element on exactly one rank')
    call check(ok_part, trim(tag)//' local elements ascending and of the right part')
    call check(ok_conn, trim(tag)//' local connectivity maps back to global')
  end subroutine check_elements

  !> Nodes: local sets, ownership, shared lists and boundary elements against brute force.
  subroutine check_nodes(tag, nnode, elem_start, elem_nodes, elem_part, decomp)
    character(len=*), intent(in) :: tag                   !< message prefix
    integer, intent(in) :: nnode                          !< nodes
    integer, intent(in) :: elem_start(:), elem_nodes(:)   !< global connectivity
    integer, intent(in) :: elem_part(:)                   !< partition
    type(decomposition_t), intent(in) :: decomp(0:)       !< all ranks
    logical :: touched(nnode, 0:size(decomp) - 1)
    integer :: owned_count(nnode), nranks, r, q, e, j, i, k, n, kq
    integer, allocatable :: want(:), mine(:), theirs(:)
    logical :: ok_local, ok_owner, ok_shared, ok_symmetric, ok_boundary, expected
    nranks = size(decomp)
    touched = .false.
    do e = 1, size(elem_part)
      do j = elem_start(e), elem_start(e + 1) - 1
        touched(elem_nodes(j), elem_part(e)) = .true.
      end do
    end do
    owned_count = 0
    ok_local = .true.
    ok_owner = .true.
    ok_shared = .true.
    ok_symmetric = .true.
    ok_boundary = .true.
    do r = 0, nranks - 1
      associate(d => decomp(r))
        ! local nodes: touched by r, or untouched and r == 0; ascending
        mine = pack([(n, n = 1, nnode)], touched(:, r) .or. &
                    (r == 0 .and. .not. any(touched, dim=2)))
        ok_local = ok_local .and. size(mine) == d%nnode_local
        if (ok_local) ok_local = all(d%node_global == mine)
        do i = 1, d%nnode_local
          n = d%node_global(i)
          if (d%node_owned(i)) owned_count(n) = owned_count(n) + 1
          if (any(touched(n, :))) then
            ok_owner = ok_owner .and. d%node_owner(i) == findloc(touched(n, :), .true., 1) - 1
          else
            ok_owner = ok_owner .and. d%node_owner(i) == 0
          end if
        end do
        ok_owner = ok_owner .and. d%nnode_owned == count(d%node_owned)
        ! neighbours: exactly the ranks sharing a node, each with the brute-force list
        k = 0
        do q = 0, nranks - 1
          if (q == r) cycle
          want = pack([(n, n = 1, nnode)], touched(:, r) .and. touched(:, q))
          if (size(want) == 0) cycle
          k = k + 1
          if (k > d%nneighbour) then
            ok_shared = .false.
            exit
          end if
          ok_shared = ok_shared .and. d%neighbour_rank(k) == q
          mine = d%node_global(d%shared_nodes(d%shared_start(k):d%shared_start(k + 1) - 1))
          ok_shared = ok_shared .and. size(mine) == size(want)
          if (ok_shared) ok_shared = all(mine == want)
          ! symmetry: q's list for r names the same global nodes in the same order
          kq = findloc(decomp(q)%neighbour_rank, r, 1)
          if (kq == 0) then
            ok_symmetric = .false.
          else
            theirs = decomp(q)%node_global(decomp(q)%shared_nodes( &
                     decomp(q)%shared_start(kq):decomp(q)%shared_start(kq + 1) - 1))
            ok_symmetric = ok_symmetric .and. size(theirs) == size(mine)
            if (ok_symmetric) ok_symmetric = all(theirs == mine)
          end if
        end do
        ok_shared = ok_shared .and. k == d%nneighbour
        ! boundary elements: touch a node that another rank's elements also touch
        do i = 1, d%nelem_local
          expected = .false.
          do j = d%elem_start_local(i), d%elem_start_local(i + 1) - 1
            n = d%node_global(d%elem_nodes_local(j))
            expected = expected .or. count(touched(n, :)) > 1
          end do
          ok_boundary = ok_boundary .and. (d%elem_on_boundary(i) .eqv. expected)
        end do
      end associate
    end do
    call check(ok_local, trim(tag)//' local nodes = nodes touched (untouched on rank 0)')
    call check(all(owned_count == 1), trim(tag)//' every node owned exactly once')
    call check(ok_owner, trim(tag)//' owner is the lowest touching rank')
    call check(ok_shared, trim(tag)//' shared-node lists match brute force')
    call check(ok_symmetric, trim(tag)//' shared-node lists symmetric')
    call check(ok_boundary, trim(tag)//' boundary elements flagged')
  end subroutine check_nodes

  !> fill_output_mesh: sizes, gathered values, and global positions in ascending-id order.
  subroutine check_output(tag, nnode, nelem, x, topo, decomp)
    character(len=*), intent(in) :: tag                   !< message prefix
    integer, intent(in) :: nnode, nelem                   !< mesh sizes
    real(wp), intent(in) :: x(:,:)                        !< coordinates
    integer, intent(in) :: topo                           !< topology of every element
    type(decomposition_t), intent(in) :: decomp(0:)       !< all ranks
    type(output_mesh_t) :: out
    integer :: node_id(nnode), elem_id(nelem), part_id(nelem), topology(nelem)
    integer :: node_rank(nnode), elem_rank(nelem), written(nnode), r, i, n
    logical :: ok_size, ok_values, ok_global
    ! ids deliberately not in index order: positions must follow ascending ids
    do n = 1, nnode
      node_id(n) = 100000 + mod(37*n, 1009)*3
    end do
    do n = 1, nelem
      elem_id(n) = 5*(nelem - n) + 2
      part_id(n) = 1 + mod(n, 3)
    end do
    topology = topo
    do n = 1, nnode
      node_rank(n) = count(node_id < node_id(n)) + 1
    end do
    do n = 1, nelem
      elem_rank(n) = count(elem_id < elem_id(n)) + 1
    end do
    written = 0
    ok_size = .true.
    ok_values = .true.
    ok_global = .true.
    do r = 0, size(decomp) - 1
      associate(d => decomp(r))
        call fill_output_mesh(d, x, node_id, topology, elem_id, part_id, out)
        ok_size = ok_size .and. out%nnode == d%nnode_local .and. out%ncell == d%nelem_local &
            .and. out%nnode_global == nnode .and. out%ncell_global == nelem &
            .and. all(shape(out%x) == [3, d%nnode_local]) .and. size(out%conn) == &
            size(d%elem_nodes_local) .and. size(out%cell_start) == d%nelem_local + 1
        if (.not. ok_size) exit
        ok_values = ok_values .and. all(out%x == x(:, d%node_global)) &
            .and. all(out%node_id == node_id(d%node_global)) &
            .and. all(out%node_owned .eqv. d%node_owned) &
            .and. all(out%topology == topo) &
            .and. all(out%cell_start == d%elem_start_local) &
            .and. all(out%conn == d%elem_nodes_local) &
            .and. all(out%cell_id == elem_id(d%elem_global)) &
            .and. all(out%cell_part == part_id(d%elem_global))
        ok_global = ok_global .and. all(out%global_node == node_rank(d%node_global)) &
            .and. all(out%global_cell == elem_rank(d%elem_global))
        do i = 1, out%nnode
          if (out%node_owned(i)) written(out%global_node(i)) = written(out%global_node(i)) + 1
        end do
      end associate
    end do
    call check(ok_size, trim(tag)//' output mesh sizes')
    call check(ok_values, trim(tag)//' output mesh values')
    call check(ok_global, trim(tag)//' output global positions follow ascending ids')
    call check(all(written == 1), trim(tag)//' owned output rows cover every node once')
  end subroutine check_output

  !> Weighted elements: parts balance the total weight, not the element count.
  subroutine check_weighted(nelem, nnode, elem_start, elem_nodes, x)
    integer, intent(in) :: nelem, nnode                   !< mesh sizes
    integer, intent(in) :: elem_start(:), elem_nodes(:)   !< connectivity
    real(wp), intent(in) :: x(:,:)                        !< coordinates
    integer :: weight(nelem), elem_part(nelem), part_weight(0:2), e
    type(status_t) :: status
    do e = 1, nelem
      weight(e) = 1
      if (x(1, elem_nodes(elem_start(e))) < 0.5_wp) weight(e) = 4
    end do
    call metis_partition_elements(nelem, nnode, elem_start, elem_nodes, 3, 3, weight, &
                                  elem_part, status)
    call check(status%ok, 'weighted: METIS succeeds')
    if (.not. status%ok) return
    part_weight = 0
    do e = 1, nelem
      part_weight(elem_part(e)) = part_weight(elem_part(e)) + weight(e)
    end do
    call check(maxval(part_weight) <= 1.1_wp*sum(weight)/3.0_wp + 4.0_wp, &
               'weighted: total weight balanced (max <= 1.1 average + max weight)')
  end subroutine check_weighted

  !> Bad requests and bad meshes come back as a status with a message, without a crash.
  subroutine check_errors(nelem, nnode, elem_start, elem_nodes)
    integer, intent(in) :: nelem, nnode                   !< mesh sizes
    integer, intent(in) :: elem_start(:), elem_nodes(:)   !< connectivity
    integer :: elem_part(nelem), bad_nodes(size(elem_nodes)), weight(nelem)
    type(status_t) :: status
    type(decomposition_t) :: decomp

    call metis_partition_elements(nelem, nnode, elem_start, elem_nodes, 2, nelem + 1, &
                                  elem_part=elem_part, status=status)
    call expect_failure(status, 'nparts > nelem')
    call metis_partition_elements(nelem, nnode, elem_start, elem_nodes, 2, 0, &
                                  elem_part=elem_part, status=status)
    call expect_failure(status, 'nparts = 0')
    bad_nodes = elem_nodes
    bad_nodes(5) = nnode + 1
    call metis_partition_elements(nelem, nnode, elem_start, bad_nodes, 2, 2, &
                                  elem_part=elem_part, status=status)
    call expect_failure(status, 'node index > nnode')
    bad_nodes(5) = 0
    call metis_partition_elements(nelem, nnode, elem_start, bad_nodes, 2, 1, &
                                  elem_part=elem_part, status=status)
    call expect_failure(status, 'node index 0 (even for one part)')
    weight = 1
    weight(3) = -1
    call metis_partition_elements(nelem, nnode, elem_start, elem_nodes, 2, 2, weight, &
                                  elem_part, status)
    call expect_failure(status, 'negative weight')
    call metis_partition_elements(nelem, nnode, elem_start(1:nelem), elem_nodes, 2, 2, &
                                  elem_part=elem_part, status=status)
    call expect_failure(status, 'elem_start too short')
    call metis_partition_elements(nelem, nnode, elem_start, elem_nodes, 0, 2, &
                                  elem_part=elem_part, status=status)
    call expect_failure(status, 'ncommon = 0')

    elem_part = 0
    elem_part(7) = 2
    call build_decomposition(0, 2, nelem, nnode, elem_start, elem_nodes, elem_part, decomp, &
                             status)
    call expect_failure(status, 'decomposition: part >= nranks')
    elem_part(7) = 1
    call build_decomposition(2, 2, nelem, nnode, elem_start, elem_nodes, elem_part, decomp, &
                             status)
    call expect_failure(status, 'decomposition: rank >= nranks')
    call build_decomposition(0, 2, nelem, nnode, elem_start, bad_nodes, elem_part, decomp, &
                             status)
    call expect_failure(status, 'decomposition: node index 0')
  end subroutine check_errors

  !> Pass when status reports a failure with a non-empty message.
  subroutine expect_failure(status, what)
    type(status_t), intent(in) :: status                  !< returned status
    character(len=*), intent(in) :: what                  !< the bad input
    logical :: has_message
    has_message = .false.
    if (allocated(status%message)) has_message = len_trim(status%message) > 0
    call check(.not. status%ok .and. has_message, 'error: '//what//' gives status with message')
  end subroutine expect_failure

end program test_partition
