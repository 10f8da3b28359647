!> Tests of the COO builder and the MUMPS wrapper: 2D Poisson (SPD), convection-diffusion
!> (unsymmetric), re-factorisation with the same pattern, inertia of a shifted Laplacian
!> (general symmetric), singular matrices, and coo_compress. Run with MEFEM_MUMPS_VERBOSE=1
!> to see MUMPS's own output.
!>
!> The matrices are sums of cell blocks of a structured grid, split unevenly among ranks,
!> some cells split in two halves on two ranks (duplicates across ranks). The right-hand
!> side b = A x_exact is computed from the same blocks, without the COO storage.
! ranks: 1 2 3
program test_mumps_solver
  use mefem_kinds, only: wp, i8
  use mefem_comm, only: comm_rank, comm_size, comm_sum, comm_is_root
  use mefem_errors, only: status_t
  use mefem_testing, only: test_start, test_finish, check, check_close, check_equal
  use mefem_sparse_assembly, only: coo_matrix_t, coo_init, coo_add_block, coo_reset_values, &
      coo_compress, coo_free
  use mefem_mumps, only: mumps_solver_t, mumps_stats_t, mumps_init, mumps_analyse, &
      mumps_factorise, mumps_solve, mumps_free, mumps_stats, MUMPS_UNSYMMETRIC, MUMPS_SPD, &
      MUMPS_SYMMETRIC, ORDERING_METIS_ND, ORDERING_PORD, ORDERING_AMD, ordering_name
  implicit none

  integer, parameter :: M = 40              !< interior nodes per direction
  real(wp), parameter :: BETA = 3.0_wp      !< convection strength (skew-symmetric part)

  call test_start('mumps_solver')
  call test_builder()
  call test_compress()
  call test_spd_and_refactorise()
  call test_orderings()
  call test_unsymmetric()
  call test_indefinite_inertia()
  call test_singular()
  call test_storage_mismatch()
  call test_finish()

contains

  !> Global dof of grid node (i, j), 0 <= i, j <= M+1; 0 on the boundary when dirichlet.
  integer function node_dof(i, j, dirichlet)
    integer, intent(in) :: i, j          !< node indices
    logical, intent(in) :: dirichlet     !< boundary nodes fixed
    if (dirichlet) then
      if (i == 0 .or. j == 0 .or. i == M + 1 .or. j == M + 1) then
        node_dof = 0
      else
        node_dof = (j - 1)*M + i
      end if
    else
      node_dof = j*(M + 2) + i + 1
    end if
  end function node_dof

  !> Block of cell (ci, cj): half of the 5-point stencil of its 4 edges, plus convection.
  subroutine cell_block(ci, cj, dirichlet, diffusion, convection, dofs, ke)
    integer, intent(in) :: ci, cj                !< cell indices, 0..M
    logical, intent(in) :: dirichlet             !< boundary nodes fixed
    real(wp), intent(in) :: diffusion            !< factor of the Laplacian part
    real(wp), intent(in) :: convection           !< factor of the skew convection part
    integer, intent(out) :: dofs(4)              !< the cell's dofs
    real(wp), intent(out) :: ke(4, 4)            !< the block
    integer, parameter :: edge(2, 4) = reshape([1, 2, 4, 3, 1, 4, 2, 3], [2, 4])
    integer :: e, p, q
    dofs = [node_dof(ci, cj, dirichlet), node_dof(ci + 1, cj, dirichlet), &
            node_dof(ci + 1, cj + 1, dirichlet), node_dof(ci, cj + 1, dirichlet)]
    ke = 0.0_wp
    do e = 1, 4
      p = edge(1, e)
      q = edge(2, e)
      ke(p, p) = ke(p, p) + 0.5_wp*diffusion
      ke(q, q) = ke(q, q) + 0.5_wp*diffusion
      ke(p, q) = ke(p, q) - 0.5_wp*diffusion
      ke(q, p) = ke(q, p) - 0.5_wp*diffusion
      if (e <= 2) then            ! horizontal edges: p left of q
        ke(p, q) = ke(p, q) + 0.25_wp*convection
        ke(q, p) = ke(q, p) - 0.25_wp*convection
      end if
    end do
  end subroutine cell_block

  !> Add this rank's cell blocks (uneven split, some cells halved on two ranks) to a, and
  !> the product of the full blocks with x_exact to y (summed over ranks by the caller).
  subroutine assemble(a, dirichlet, diffusion, convection, shift, symmetric, reverse, &
                      x_exact, y)
    type(coo_matrix_t), intent(inout) :: a   !< matrix
    logical, intent(in) :: dirichlet         !< boundary nodes fixed
    real(wp), intent(in) :: diffusion, convection  !< factors of the two parts
    real(wp), intent(in) :: shift            !< subtracted from the diagonal (one per dof)
    logical, intent(in) :: symmetric         !< lower-triangle storage
    logical, intent(in) :: reverse           !< visit the cells in reverse order
    real(wp), intent(in) :: x_exact(:)       !< vector for the product
    real(wp), intent(inout) :: y(:)          !< this rank's part of A x_exact
    integer :: ci, cj, c, h, owner, second, nr, me, dofs(4), i, j, k, first, last, step
    real(wp) :: ke(4, 4), weight
    nr = comm_size()
    me = comm_rank()
    first = 0
    last = (M + 1)**2 - 1
    step = 1
    if (reverse) then
      first = last
      last = 0
      step = -1
    end if
    do c = first, last, step
      ci = mod(c, M + 1)
      cj = c/(M + 1)
      h = mod(ci*7 + cj*11, 17)
      owner = min(nr - 1, h*h*nr/289)
      second = owner
      if (mod(ci + 2*cj, 5) == 0) second = mod(owner + 1, nr)
      if (me /= owner .and. me /= second) cycle
      weight = 1.0_wp
      if (second /= owner) weight = 0.5_wp
      call cell_block(ci, cj, dirichlet, weight*diffusion, weight*convection, dofs, ke)
      call coo_add_block(a, dofs, ke, symmetric)
      do j = 1, 4
        do i = 1, 4
          if (dofs(i) > 0 .and. dofs(j) > 0) y(dofs(i)) = y(dofs(i)) + ke(i, j)*x_exact(dofs(j))
        end do
      end do
    end do
    if (shift /= 0.0_wp) then      ! diagonal shift: rank 0 adds it, as 1x1 blocks
      if (me == 0) then
        do k = 1, a%n
          call coo_add_block(a, [k], reshape([-shift], [1, 1]), symmetric)
          y(k) = y(k) - shift*x_exact(k)
        end do
      end if
    end if
  end subroutine assemble

  !> A known solution with no symmetry.
  subroutine exact_solution(x)
    real(wp), intent(out) :: x(:)   !< values
    integer :: k
    do k = 1, size(x)
      x(k) = 1.0_wp + sin(0.37_wp*k) + 0.001_wp*k
    end do
  end subroutine exact_solution

  !> Relative 2-norm error.
  real(wp) function relative_error(x, x_exact)
    real(wp), intent(in) :: x(:), x_exact(:)   !< computed and exact
    relative_error = norm2(x - x_exact)/norm2(x_exact)
  end function relative_error

  !> The builder: skipped dofs, lower triangle, growth from a tiny capacity, refill order.
  subroutine test_builder()
    type(coo_matrix_t) :: a
    real(wp) :: ke(3, 3)
    integer(i8) :: id
    integer :: k
    call coo_init(a, 5, 1)
    ke = reshape([1.0_wp, 2.0_wp, 3.0_wp, 4.0_wp, 5.0_wp, 6.0_wp, 7.0_wp, 8.0_wp, 9.0_wp], &
                 [3, 3])
    call coo_add_block(a, [2, 0, 4], ke, .false.)
    call check(a%nnz == 4_i8, 'full block with one fixed dof stores 4 entries')
    call check(all(a%row(1:4) == [2, 4, 2, 4]) .and. all(a%col(1:4) == [2, 2, 4, 4]) .and. &
               all(a%val(1:4) == [1.0_wp, 3.0_wp, 7.0_wp, 9.0_wp]), 'full block positions')
    call coo_free(a)
    call coo_init(a, 5, 1)
    do k = 1, 100
      call coo_add_block(a, [5, 1, 3], ke, .true.)
    end do
    call check(a%nnz == 600_i8, 'symmetric block stores 6 of 9 entries (100 blocks)')
    call check(all(a%row(1:a%nnz) >= a%col(1:a%nnz)), 'symmetric storage is lower triangle')
    call check(size(a%row) >= 600 .and. size(a%row) < 1200, 'capacity grew by doubling')
    call check(a%row(2) == 5 .and. a%col(2) == 1 .and. a%val(2) == 4.0_wp .and. &
               a%row(3) == 1 .and. a%col(3) == 1 .and. a%val(3) == 5.0_wp, &
               'symmetric block keeps ke(i,j) with dofs(i) >= dofs(j)')
    id = a%pattern_id
    call coo_reset_values(a)
    call check(all(a%val(1:a%nnz) == 0.0_wp), 'reset zeroes the values')
    do k = 1, 100
      call coo_add_block(a, [5, 1, 3], 2.0_wp*ke, .true.)
    end do
    call check(a%pattern_id == id .and. a%nnz == 600_i8, 'same add order keeps the pattern')
    call check(a%val(1) == 2.0_wp, 'refilled value')
    call coo_reset_values(a)
    call coo_add_block(a, [1, 5, 3], ke, .true.)
    call check(a%pattern_id /= id .and. a%nnz == 600_i8, 'other add order changes the pattern')
    call coo_free(a)
  end subroutine test_builder

  !> coo_compress: sorted, unique, sums equal a dense reference; refill in any order.
  subroutine test_compress()
    type(coo_matrix_t) :: a
    real(wp) :: dense(12, 12), check_dense(12, 12), ke(4, 4)
    integer :: dofs(4), k, i, j, distinct
    integer(i8) :: id
    logical :: ordered, touched(12, 12)
    real(wp) :: r
    call coo_init(a, 12, 4)
    dense = 0.0_wp
    do k = 1, 300
      do i = 1, 4
        dofs(i) = mod(k*(i + 2) + i*i*5, 13)       ! 0..12, 0 = skipped
      end do
      do j = 1, 4
        do i = 1, 4
          r = real(mod(k*31 + i*7 + j*3, 19), wp) - 9.0_wp
          ke(i, j) = r
          if (dofs(i) > 0 .and. dofs(j) > 0) dense(dofs(i), dofs(j)) = &
              dense(dofs(i), dofs(j)) + r
        end do
      end do
      call coo_add_block(a, dofs, ke, .false.)
    end do
    call coo_compress(a)
    ordered = .true.
    do k = 2, int(a%nnz)
      if (a%row(k) < a%row(k-1) .or. (a%row(k) == a%row(k-1) .and. a%col(k) <= a%col(k-1))) &
          ordered = .false.
    end do
    call check(ordered, 'compress sorts by (row, col), no duplicates')
    check_dense = 0.0_wp
    distinct = 0
    do k = 1, int(a%nnz)
      check_dense(a%row(k), a%col(k)) = check_dense(a%row(k), a%col(k)) + a%val(k)
    end do
    call check(maxval(abs(check_dense - dense)) <= 1.0e-12_wp, 'compress keeps the sums')
    ! positions touched at least once (a sum may be zero, the position stays)
    call touched_positions(touched)
    distinct = count(touched)
    call check_equal(int(a%nnz), distinct, 'compressed count = distinct positions')
    id = a%pattern_id
    call coo_reset_values(a)
    do k = 300, 1, -1                  ! reverse order: found by binary search
      do i = 1, 4
        dofs(i) = mod(k*(i + 2) + i*i*5, 13)
      end do
      do j = 1, 4
        do i = 1, 4
          ke(i, j) = 2.0_wp*(real(mod(k*31 + i*7 + j*3, 19), wp) - 9.0_wp)
        end do
      end do
      call coo_add_block(a, dofs, ke, .false.)
    end do
    check_dense = 0.0_wp
    do k = 1, int(a%nnz)
      check_dense(a%row(k), a%col(k)) = check_dense(a%row(k), a%col(k)) + a%val(k)
    end do
    call check(a%pattern_id == id .and. a%sorted, 'refill of a compressed matrix keeps it')
    call check(maxval(abs(check_dense - 2.0_wp*dense)) <= 1.0e-12_wp, &
               'refill of a compressed matrix in reverse order')
    i = findloc(touched(:, 1), .false., dim=1)     ! a position no block touched
    call check(i > 0, 'test matrix has an untouched position')
    if (i > 0) then
      call coo_add_block(a, [i, 1], reshape([0.5_wp, 1.0_wp, 2.0_wp, 4.0_wp], [2, 2]), .false.)
      check_dense = 0.0_wp
      do k = 1, int(a%nnz)
        check_dense(a%row(k), a%col(k)) = check_dense(a%row(k), a%col(k)) + a%val(k)
      end do
      dense = 2.0_wp*dense
      dense(i, i) = dense(i, i) + 0.5_wp
      dense(1, i) = dense(1, i) + 1.0_wp
      dense(i, 1) = dense(i, 1) + 2.0_wp
      dense(1, 1) = dense(1, 1) + 4.0_wp
      call check(a%pattern_id /= id .and. .not. a%sorted .and. a%nnz > int(distinct, i8) .and. &
                 maxval(abs(check_dense - dense)) <= 1.0e-12_wp, &
                 'a new position in a compressed matrix is appended (pattern changes)')
    end if
    call coo_free(a)
  end subroutine test_compress

  !> Positions of the reference that some block touched.
  subroutine touched_positions(touched)
    logical, intent(out) :: touched(12, 12)   !< true where an entry was added
    integer :: kk, ii, jj, d(4)
    touched = .false.
    do kk = 1, 300
      do ii = 1, 4
        d(ii) = mod(kk*(ii + 2) + ii*ii*5, 13)
      end do
      do jj = 1, 4
        do ii = 1, 4
          if (d(ii) > 0 .and. d(jj) > 0) touched(d(ii), d(jj)) = .true.
        end do
      end do
    end do
  end subroutine touched_positions

  !> (a) SPD Poisson, (c) re-factorisation with new values and the same pattern, and the
  !> same system again after coo_compress.
  subroutine test_spd_and_refactorise()
    type(coo_matrix_t) :: a
    type(mumps_solver_t) :: s
    type(status_t) :: status
    type(mumps_stats_t) :: st
    real(wp), allocatable :: x_exact(:), b(:), x(:)
    integer(i8) :: id
    integer :: changed
    call dirichlet_system(16, 1.0_wp, 0.0_wp, 0.0_wp, .true., a, x_exact, b, x)
    call mumps_init(s, MUMPS_SPD, status)
    call check(status%ok, 'init SPD')
    call mumps_analyse(s, a, status)
    call check(status%ok, 'analyse SPD Poisson')
    call mumps_factorise(s, a, status)
    call check(status%ok, 'factorise SPD Poisson')
    call mumps_solve(s, b, x, status)
    call check(status%ok, 'solve SPD Poisson')
    call check(relative_error(x, x_exact) < 1.0e-10_wp, 'SPD Poisson: relative error < 1e-10')
    st = mumps_stats(s)
    call check(st%factor_entries > 0_i8 .and. st%factor_entries_estimated > 0_i8, &
               'stats: entries in factors')
    call check(st%ordering_used >= 0 .and. st%memory_total_mb >= st%memory_max_mb .and. &
               st%memory_max_mb >= 0, 'stats: ordering and memory')
    call check_equal(st%negative_pivots, 0, 'SPD: no negative pivots')
    call check(st%time_factorisation >= 0.0_wp .and. st%time_solve >= 0.0_wp, 'stats: times')

    ! (c) new values, same positions: no re-analysis
    id = a%pattern_id
    call coo_reset_values(a)
    b = 0.0_wp
    call assemble(a, .true., 2.5_wp, 0.0_wp, -0.75_wp, .true., .false., x_exact, b)
    call comm_sum(b)
    changed = merge(1, 0, a%pattern_id /= id)
    call comm_sum(changed)
    call check(changed == 1, 'added diagonal blocks (rank 0) change the pattern on rank 0 only')
    call mumps_factorise(s, a, status)
    st = mumps_stats(s)
    call check(status%ok .and. st%n_analyses == 2, 'new pattern is re-analysed')
    call mumps_solve(s, b, x, status)
    call check(status%ok .and. relative_error(x, x_exact) < 1.0e-10_wp, &
               'shifted SPD system: relative error < 1e-10')
    id = a%pattern_id
    call coo_reset_values(a)
    b = 0.0_wp
    call assemble(a, .true., 0.5_wp, 0.0_wp, -2.0_wp, .true., .false., x_exact, b)
    call comm_sum(b)
    call check(a%pattern_id == id, 'same add order keeps the pattern (Newton re-assembly)')
    call mumps_factorise(s, a, status)
    st = mumps_stats(s)
    call check(status%ok .and. st%n_analyses == 2 .and. st%n_factorisations == 3, &
               're-factorised without re-analysis')
    call mumps_solve(s, b, x, status)
    call check(status%ok .and. relative_error(x, x_exact) < 1.0e-10_wp, &
               're-factorised with new values: relative error < 1e-10')

    ! the same system compressed (sorted, summed): new pattern, same solution
    call coo_compress(a)
    call mumps_factorise(s, a, status)
    st = mumps_stats(s)
    call check(status%ok .and. st%n_analyses == 3, 'compressed: re-analysed')
    call mumps_solve(s, b, x, status)
    call check(status%ok .and. relative_error(x, x_exact) < 1.0e-10_wp, &
               'compressed matrix: relative error < 1e-10')
    call mumps_free(s)
    call coo_free(a)
  end subroutine test_spd_and_refactorise

  !> The Poisson system with each fill-reducing ordering mefem offers: the METIS nested
  !> dissection mefem computes itself (the default: the pattern gathered on rank 0, the order
  !> given to MUMPS), PORD and AMD; the same solution, and MUMPS reports the ordering it used.
  subroutine test_orderings()
    integer, parameter :: ORDERINGS(3) = [ORDERING_METIS_ND, ORDERING_PORD, ORDERING_AMD]
    type(coo_matrix_t) :: a
    type(mumps_solver_t) :: s
    type(mumps_stats_t) :: st
    type(status_t) :: status
    real(wp), allocatable :: x_exact(:), b(:), x(:)
    integer :: k
    call dirichlet_system(16, 1.0_wp, BETA, 0.0_wp, .false., a, x_exact, b, x)
    do k = 1, size(ORDERINGS)
      call mumps_init(s, MUMPS_UNSYMMETRIC, status, ordering=ORDERINGS(k))
      call mumps_factorise(s, a, status)
      call mumps_solve(s, b, x, status)
      st = mumps_stats(s)
      call check(status%ok .and. relative_error(x, x_exact) < 1.0e-10_wp, &
                 ordering_name(ORDERINGS(k))//': relative error < 1e-10')
      call check_equal(st%ordering_used, ORDERINGS(k), ordering_name(ORDERINGS(k))// &
                       ': the ordering MUMPS used')
      if (comm_is_root()) print '(4x,a,i0,a)', ordering_name(ORDERINGS(k))//': ', &
          st%factor_entries, ' entries in the factors'
      call mumps_free(s)
    end do
    call mumps_init(s, MUMPS_UNSYMMETRIC, status)
    call mumps_factorise(s, a, status)
    st = mumps_stats(s)
    call check_equal(st%ordering_used, ORDERING_METIS_ND, 'default ordering: METIS nested '// &
                     'dissection')
    call mumps_free(s)
    call coo_free(a)
  end subroutine test_orderings

  !> The Dirichlet system of the M x M grid with assemble's coefficients: a (COO of the given
  !> initial capacity), the exact solution, b = A x_exact summed over the ranks, and x
  !> allocated for the solution.
  subroutine dirichlet_system(capacity, diffusion, convection, shift, symmetric, a, x_exact, &
                              b, x)
    integer, intent(in) :: capacity                  !< initial COO capacity
    real(wp), intent(in) :: diffusion, convection    !< factors of the two parts
    real(wp), intent(in) :: shift                    !< subtracted from the diagonal
    logical, intent(in) :: symmetric                 !< lower-triangle storage
    type(coo_matrix_t), intent(out) :: a             !< the matrix
    real(wp), allocatable, intent(out) :: x_exact(:), b(:), x(:)  !< (M*M) vectors
    allocate(x_exact(M*M), b(M*M), x(M*M))
    call exact_solution(x_exact)
    call coo_init(a, M*M, capacity)
    b = 0.0_wp
    call assemble(a, .true., diffusion, convection, shift, symmetric, .false., x_exact, b)
    call comm_sum(b)
  end subroutine dirichlet_system

  !> (b) unsymmetric convection-diffusion.
  subroutine test_unsymmetric()
    type(coo_matrix_t) :: a
    type(mumps_solver_t) :: s
    type(mumps_stats_t) :: st
    type(status_t) :: status
    real(wp), allocatable :: x_exact(:), b(:), x(:)
    call dirichlet_system(1000, 1.0_wp, BETA, 0.0_wp, .false., a, x_exact, b, x)
    call mumps_init(s, MUMPS_UNSYMMETRIC, status)
    call mumps_analyse(s, a, status)
    call mumps_factorise(s, a, status)
    call check(status%ok, 'factorise unsymmetric')
    call mumps_solve(s, b, x, status)
    call check(status%ok .and. relative_error(x, x_exact) < 1.0e-10_wp, &
               'unsymmetric convection-diffusion: relative error < 1e-10')
    ! re-factorise with other values (cells visited in the same order)
    call coo_reset_values(a)
    b = 0.0_wp
    call assemble(a, .true., 3.0_wp, -2.0_wp*BETA, 0.0_wp, .false., .false., x_exact, b)
    call comm_sum(b)
    call mumps_factorise(s, a, status)
    call mumps_solve(s, b, x, status)
    st = mumps_stats(s)
    call check(status%ok .and. st%n_analyses == 1 .and. &
               relative_error(x, x_exact) < 1.0e-10_wp, &
               'unsymmetric re-factorisation, same pattern: relative error < 1e-10')
    call mumps_free(s)
    call coo_free(a)
  end subroutine test_unsymmetric

  !> General symmetric (SYM=2): the negative pivots of L - sigma I are the eigenvalues of the
  !> 5-point Laplacian L below sigma (Sylvester's law of inertia).
  subroutine test_indefinite_inertia()
    type(coo_matrix_t) :: a
    type(mumps_solver_t) :: s
    type(mumps_stats_t) :: st
    type(status_t) :: status
    real(wp), allocatable :: x_exact(:), b(:), x(:)
    real(wp), parameter :: SIGMA = 0.9_wp
    real(wp) :: lambda, pi, closest
    integer :: j, k, below
    pi = acos(-1.0_wp)
    below = 0
    closest = huge(1.0_wp)
    do k = 1, M
      do j = 1, M
        lambda = 4.0_wp - 2.0_wp*cos(j*pi/(M + 1)) - 2.0_wp*cos(k*pi/(M + 1))
        if (lambda < SIGMA) below = below + 1
        closest = min(closest, abs(lambda - SIGMA))
      end do
    end do
    call check(closest > 1.0e-3_wp, 'shift is away from the eigenvalues')
    call dirichlet_system(1000, 1.0_wp, 0.0_wp, SIGMA, .true., a, x_exact, b, x)
    call mumps_init(s, MUMPS_SYMMETRIC, status)
    call mumps_factorise(s, a, status)       ! analyses by itself
    call check(status%ok, 'factorise indefinite symmetric')
    st = mumps_stats(s)
    call check_equal(st%negative_pivots, below, &
                     'negative pivots = eigenvalues below the shift')
    call mumps_solve(s, b, x, status)
    call check(status%ok .and. relative_error(x, x_exact) < 1.0e-8_wp, &
               'indefinite symmetric: relative error < 1e-8')
    call mumps_free(s)
    call coo_free(a)
  end subroutine test_indefinite_inertia

  !> (d) singular matrices: an unknown with no entry (zero row and column) is reported;
  !> the pure Neumann Laplacian either is reported or gives a consistent solution.
  subroutine test_singular()
    type(coo_matrix_t) :: a
    type(mumps_solver_t) :: s
    type(status_t) :: status
    real(wp), allocatable :: x_exact(:), b(:), x(:)
    integer :: n, kind, k
    character(len=*), parameter :: names(0:1) = ['unsymmetric', 'SPD        ']
    real(wp) :: offset
    do kind = MUMPS_UNSYMMETRIC, MUMPS_SPD
      n = M*M + 1                                     ! unknown n is never touched
      allocate(x_exact(n), b(n), x(n))
      call exact_solution(x_exact)
      x_exact(n) = 0.0_wp
      call coo_init(a, n, 1000)
      b = 0.0_wp
      call assemble(a, .true., 1.0_wp, 0.0_wp, 0.0_wp, kind == MUMPS_SPD, .false., x_exact, b)
      call comm_sum(b)
      call mumps_init(s, kind, status)
      call mumps_factorise(s, a, status)
      call check(.not. status%ok, trim(names(kind))//': zero row/column is reported')
      if (.not. status%ok) then
        call check(index(status%message, 'singular') > 0, &
                   trim(names(kind))//': message says singular', status%message)
        if (comm_is_root()) write(*, '(a)') '  message: '//status%message
      end if
      call mumps_solve(s, b, x, status)
      call check(.not. status%ok, trim(names(kind))//': solve after failed factorisation '// &
                 'returns an error')
      call mumps_free(s)
      call coo_free(a)
      deallocate(x_exact, b, x)
    end do

    ! pure Neumann (no boundary fixed): singular by one constant mode, zero pivot = roundoff
    n = (M + 2)**2
    allocate(x_exact(n), b(n), x(n))
    call exact_solution(x_exact)
    do kind = MUMPS_UNSYMMETRIC, MUMPS_SYMMETRIC, MUMPS_SYMMETRIC
      call coo_init(a, n, 1000)
      b = 0.0_wp
      call assemble(a, .false., 1.0e8_wp, 0.0_wp, 0.0_wp, kind /= MUMPS_UNSYMMETRIC, .false., &
                    x_exact, b)
      call mumps_init(s, kind, status)
      call mumps_factorise(s, a, status)
      call check(.not. status%ok .and. index(status%message, 'zero pivots') > 0, &
                 'Neumann Laplacian x 1e8, SYM='//char(48 + kind)//': null pivot reported')
      if (comm_is_root() .and. .not. status%ok) write(*, '(a)') '  message: '//status%message
      call mumps_free(s)
      call coo_free(a)
    end do

    ! the null pivot threshold is relative: a regular matrix of tiny scale is not singular
    deallocate(x_exact, b, x)
    allocate(x_exact(M*M), b(M*M), x(M*M))
    call exact_solution(x_exact)
    do kind = MUMPS_UNSYMMETRIC, MUMPS_SYMMETRIC, MUMPS_SYMMETRIC
      call coo_init(a, M*M, 1000)
      b = 0.0_wp
      call assemble(a, .true., 1.0e-15_wp, 1.0e-15_wp*merge(BETA, 0.0_wp, kind == 0), 0.0_wp, &
                    kind /= MUMPS_UNSYMMETRIC, .false., x_exact, b)
      call comm_sum(b)
      call mumps_init(s, kind, status)
      call mumps_factorise(s, a, status)
      if (status%ok) call mumps_solve(s, b, x, status)
      call check(status%ok .and. relative_error(x, x_exact) < 1.0e-10_wp, &
                 'regular matrix x 1e-15, SYM='//char(48 + kind)//': solved, no null pivot')
      call mumps_free(s)
      call coo_free(a)
    end do
    deallocate(x_exact, b, x)
    allocate(x_exact(n), b(n), x(n))
    call exact_solution(x_exact)

    ! SPD mode: MUMPS has no null pivot detection; either "not positive definite" (last
    ! pivot negative) or one of the solutions, x_exact + constant (b is in the range)
    call coo_init(a, n, 1000)
    b = 0.0_wp
    call assemble(a, .false., 1.0_wp, 0.0_wp, 0.0_wp, .true., .false., x_exact, b)
    call comm_sum(b)
    call mumps_init(s, MUMPS_SPD, status)
    call mumps_factorise(s, a, status)
    if (status%ok) call mumps_solve(s, b, x, status)
    if (.not. status%ok) then
      if (comm_is_root()) write(*, '(a)') '  SPD Neumann reported: '//status%message
      call check(index(status%message, 'not positive definite') > 0, &
                 'SPD Neumann Laplacian: reported as not positive definite')
    else
      offset = sum(x - x_exact)/n
      if (comm_is_root()) write(*, '(a,es10.2)') '  SPD Neumann Laplacian not detected; '// &
          'solution offset by a constant ', offset
      do k = 1, n
        x(k) = x(k) - offset
      end do
      call check(all(x == x) .and. relative_error(x, x_exact) < 1.0e-6_wp, &
                 'SPD Neumann Laplacian not detected: solution = exact + constant')
    end if
    call mumps_free(s)
    call coo_free(a)

    ! SPD mode given an indefinite matrix (shifted Laplacian)
    call coo_init(a, n, 1000)
    b = 0.0_wp
    call assemble(a, .false., 1.0_wp, 0.0_wp, 0.9_wp, .true., .false., x_exact, b)
    call mumps_init(s, MUMPS_SPD, status)
    call mumps_factorise(s, a, status)
    call check(.not. status%ok .and. index(status%message, 'not positive definite') > 0, &
               'indefinite matrix in SPD mode is reported', status%message)
    call mumps_free(s)
    call coo_free(a)
  end subroutine test_singular

  !> A full-storage matrix given to a symmetric solver is refused (on every rank).
  subroutine test_storage_mismatch()
    type(coo_matrix_t) :: a
    type(mumps_solver_t) :: s
    type(status_t) :: status
    real(wp) :: x_exact(M*M), b(M*M)
    call exact_solution(x_exact)
    b = 0.0_wp
    call coo_init(a, M*M, 1000)
    call assemble(a, .true., 1.0_wp, 0.0_wp, 0.0_wp, .false., .false., x_exact, b)
    call mumps_init(s, MUMPS_SPD, status)
    call mumps_analyse(s, a, status)
    call check(.not. status%ok .and. index(status%message, 'lower') > 0, &
               'symmetric solver refuses full storage')
    call mumps_free(s)
    call coo_free(a)
  end subroutine test_storage_mismatch

end program test_mumps_solver
