!> One-point hexahedron kernels (mefem_hexahedron): the reference geometry's identities on a
!> distorted hexahedron (sum B = 0, sum X (x) B = I, volumes, hourglass vectors orthogonal to
!> the linear fields), the collapsed tetrahedron's gradients are the linear tetrahedron's, the
!> stiffness-form hourglass forces are the derivative of their energy and their tangent the
!> derivative of the forces (central differences), the energy is objective, and the block
!> kernel gives the single-cell routine's forces.
program test_hexahedron
  use mefem_kinds, only: wp, i1
  use mefem_testing, only: test_start, test_finish, check, check_close
  use mefem_strings, only: rtoa
  use mefem_hexahedron, only: HOURGLASS_MODES, HOURGLASS_VECTORS, hexahedron_reference, &
                              hourglass_stiffness_cell, &
                              block_hourglass_forces, hourglass_mode_metric
  use mefem_cell_finite_strain, only: cell_deformation_gradient, block_adjugate
  use mefem_material_state, only: BLOCK_POINTS
  implicit none

  real(wp), parameter :: CUBE(3, 8) = reshape([0.0_wp, 0.0_wp, 0.0_wp,  1.0_wp, 0.0_wp, 0.0_wp, &
      1.0_wp, 1.0_wp, 0.0_wp,  0.0_wp, 1.0_wp, 0.0_wp,  0.0_wp, 0.0_wp, 1.0_wp, &
      1.0_wp, 0.0_wp, 1.0_wp,  1.0_wp, 1.0_wp, 1.0_wp,  0.0_wp, 1.0_wp, 1.0_wp], [3, 8])

  call test_start('hexahedron')
  call reference_identities()
  call affine_volume()
  call collapsed_tetrahedron()
  call stiffness_derivatives()
  call objectivity()
  call block_matches_cell()
  call test_finish()

contains

  !> A distorted hexahedron: the unit cube with its corners moved at random by up to 0.2.
  subroutine distorted_hexahedron(x)
    real(wp), intent(out) :: x(3, 8)
    call random_number(x)
    x = CUBE + 0.4_wp*(x - 0.5_wp)
  end subroutine distorted_hexahedron

  subroutine reference_identities()
    real(wp) :: x(3, 8), volume, grad(3, 8), node_volume(8), gamma(8, HOURGLASS_MODES)
    real(wp) :: xb(3, 3), eye(3, 3), lin(HOURGLASS_MODES, 3)
    integer :: i
    call distorted_hexahedron(x)
    call hexahedron_reference(x, volume, grad, node_volume, gamma)
    xb = matmul(x, transpose(grad))              ! sum_I X_I (x) B_I
    eye = 0.0_wp
    do i = 1, 3
      eye(i, i) = 1.0_wp
    end do
    call check(volume > 0.0_wp, 'distorted hexahedron: positive volume')
    call check(maxval(abs(sum(grad, dim=2))) < 1e-14_wp, 'sum of the uniform gradients is zero')
    call check(maxval(abs(xb - eye)) < 1e-14_wp, 'sum X_I (x) B_I = I (linear fields exact)', &
               rtoa(maxval(abs(xb - eye))))
    call check_close(sum(node_volume), volume, 1e-14_wp, 'nodal volumes sum to the volume')
    lin = matmul(transpose(gamma), transpose(x))
    call check(maxval(abs(sum(gamma, dim=1))) < 1e-14_wp .and. maxval(abs(lin)) < 1e-14_wp, &
               'hourglass vectors orthogonal to the constant and linear fields', &
               rtoa(maxval(abs(lin))))
  end subroutine reference_identities

  !> An affine image of the cube (a parallelepiped): volume det(A), nodal volumes V/8, gamma the
  !> base vectors, the mode metric's bound exact (8/m).
  subroutine affine_volume()
    real(wp) :: a(3, 3), x(3, 8), volume, grad(3, 8), node_volume(8), gamma(8, HOURGLASS_MODES)
    real(wp) :: det, mass(8)
    a = reshape([1.3_wp, 0.2_wp, -0.1_wp, 0.3_wp, 0.9_wp, 0.2_wp, 0.1_wp, -0.2_wp, 1.1_wp], [3, 3])
    x = matmul(a, CUBE) + 0.5_wp
    det = a(1, 1)*(a(2, 2)*a(3, 3) - a(3, 2)*a(2, 3)) - a(1, 2)*(a(2, 1)*a(3, 3) - &
          a(3, 1)*a(2, 3)) + a(1, 3)*(a(2, 1)*a(3, 2) - a(3, 1)*a(2, 2))
    call hexahedron_reference(x, volume, grad, node_volume, gamma)
    call check_close(volume, det, 1e-14_wp, 'parallelepiped: volume det A')
    call check(maxval(abs(node_volume - det/8.0_wp)) < 1e-14_wp, 'parallelepiped: V/8 per node')
    call check(maxval(abs(abs(gamma) - 1.0_wp)) < 1e-13_wp, 'parallelepiped: gamma = +-1')
    mass = 2.0_wp
    call check_close(hourglass_mode_metric(8, gamma, mass), 8.0_wp/2.0_wp, 1e-13_wp, &
                     'parallelepiped: mode metric bound 8/m')
  end subroutine affine_volume

  !> N1 N2 N3 N4 N4 N4 N4 N4: the merged uniform gradients are the linear tetrahedron's and the
  !> merged hourglass vectors vanish.
  subroutine collapsed_tetrahedron()
    real(wp) :: t(3, 4), x(3, 8), volume, grad(3, 8), node_volume(8), gamma(8, HOURGLASS_MODES)
    real(wp) :: merged(3, 4), gm(4, HOURGLASS_MODES), edges(3, 3), linear(3, 4), inv(3, 3)
    integer :: k
    t = reshape([0.1_wp, 0.0_wp, 0.0_wp, 1.2_wp, 0.1_wp, 0.0_wp, 0.3_wp, 0.9_wp, 0.1_wp, &
                 0.2_wp, 0.3_wp, 1.1_wp], [3, 4])
    x(:, 1:3) = t(:, 1:3)
    do k = 4, 8
      x(:, k) = t(:, 4)
    end do
    call hexahedron_reference(x, volume, grad, node_volume, gamma)
    merged(:, 1:3) = grad(:, 1:3)
    merged(:, 4) = sum(grad(:, 4:8), dim=2)
    gm(1:3, :) = gamma(1:3, :)
    gm(4, :) = sum(gamma(4:8, :), dim=1)
    do k = 1, 3
      edges(:, k) = t(:, k + 1) - t(:, 1)
    end do
    inv = inverse(edges)                       ! rows: gradients of the barycentric 2, 3, 4
    linear(:, 2:4) = transpose(inv)
    linear(:, 1) = -sum(linear(:, 2:4), dim=2)
    call check(maxval(abs(merged - linear)) < 1e-13_wp, 'collapsed tetrahedron: the linear '// &
               'tetrahedron''s gradients', rtoa(maxval(abs(merged - linear))))
    call check(maxval(abs(gm)) < 1e-13_wp, 'collapsed tetrahedron: no hourglass vectors', &
               rtoa(maxval(abs(gm))))
    ! (its volume is not the tetrahedron's: the bottom face N1 N2 N3 N4 is a bilinear surface
    ! through the tetrahedron; mefem computes such elements as linear tetrahedra)
    call check(abs(volume - abs(det3(edges))/6.0_wp) > 1e-3_wp*volume, 'collapsed '// &
               'tetrahedron: the trilinear map''s volume is not the tetrahedron''s')
  end subroutine collapsed_tetrahedron

  !> Forces = dW/dx and tangent = df/dx by central differences, at a finite deformation with
  !> hourglass displacements.
  subroutine stiffness_derivatives()
    real(wp) :: x(3, 8), volume, grad(3, 8), node_volume(8), gamma(8, HOURGLASS_MODES)
    real(wp) :: u(3, 8), up(3, 8), force(3, 8), fp(3, 8), fm(3, 8), ke(24, 24), fd(24, 24)
    real(wp) :: kp(24, 24), k6(6), wp_, wm, dw(3, 8), energy
    real(wp), parameter :: H = 1.0e-6_wp
    integer :: a, i
    call distorted_hexahedron(x)
    call hexahedron_reference(x, volume, grad, node_volume, gamma)
    call random_number(u)
    u = 0.2_wp*(u - 0.5_wp)
    k6 = [3.0_wp, 2.0_wp, 4.0_wp, 0.5_wp, -0.3_wp, 0.2_wp]
    call evaluate(grad, gamma, k6, u, force, ke, energy)
    do a = 1, 8
      do i = 1, 3
        up = u
        up(i, a) = u(i, a) + H
        call evaluate(grad, gamma, k6, up, fp, kp, wp_)
        up(i, a) = u(i, a) - H
        call evaluate(grad, gamma, k6, up, fm, kp, wm)
        fd(:, 3*(a-1) + i) = reshape(fp - fm, [24])/(2.0_wp*H)
        dw(i, a) = (wp_ - wm)/(2.0_wp*H)
      end do
    end do
    call check(maxval(abs(dw - force)) < 1e-7_wp*maxval(abs(force)), 'hourglass forces = dW/dx', &
               rtoa(maxval(abs(dw - force))/maxval(abs(force))))
    call check(maxval(abs(fd - ke)) < 1e-6_wp*maxval(abs(ke)), 'hourglass tangent = df/dx', &
               rtoa(maxval(abs(fd - ke))/maxval(abs(ke))))
    call check(maxval(abs(ke - transpose(ke))) < 1e-12_wp*maxval(abs(ke)), &
               'hourglass tangent symmetric')
  end subroutine stiffness_derivatives

  !> Hourglass forces, tangent and energy of one cell at displacements uu.
  subroutine evaluate(grad, gamma, k6, uu, ff, kk, w)
    real(wp), intent(in) :: grad(3, 8), gamma(8, HOURGLASS_MODES), k6(6), uu(3, 8)
    real(wp), intent(out) :: ff(3, 8), kk(24, 24), w
    real(wp) :: f(3, 3)
    call cell_deformation_gradient(3, 8, grad, uu, f)
    call hourglass_stiffness_cell(8, grad, gamma, k6, uu, f, ff, kk, w)
  end subroutine evaluate

  !> A rigid rotation superposed on a deformed state leaves the energy unchanged and rotates
  !> the forces.
  subroutine objectivity()
    real(wp) :: x(3, 8), volume, grad(3, 8), node_volume(8), gamma(8, HOURGLASS_MODES)
    real(wp) :: u(3, 8), ur(3, 8), r(3, 3), f(3, 3), force(3, 8), fr(3, 8), ke(24, 24), w, w2
    real(wp) :: k6(6), c, s
    call distorted_hexahedron(x)
    call hexahedron_reference(x, volume, grad, node_volume, gamma)
    call random_number(u)
    u = 0.2_wp*(u - 0.5_wp)
    k6 = [3.0_wp, 2.0_wp, 4.0_wp, 0.5_wp, -0.3_wp, 0.2_wp]
    c = cos(1.1_wp)
    s = sin(1.1_wp)
    r = reshape([c, s, 0.0_wp, -s*0.6_wp, c*0.6_wp, 0.8_wp, s*0.8_wp, -c*0.8_wp, 0.6_wp], [3, 3])
    ur = matmul(r, x + u) - x                    ! x -> R (X + u)
    call cell_deformation_gradient(3, 8, grad, u, f)
    call hourglass_stiffness_cell(8, grad, gamma, k6, u, f, force, ke, w)
    call cell_deformation_gradient(3, 8, grad, ur, f)
    call hourglass_stiffness_cell(8, grad, gamma, k6, ur, f, fr, ke, w2)
    call check(w > 0.0_wp, 'objectivity: the deformed state has hourglass energy')
    call check_close(w2, w, 1e-12_wp, 'objectivity: the energy is unchanged by a rotation')
    call check(maxval(abs(fr - matmul(r, force))) < 1e-12_wp*maxval(abs(force)), &
               'objectivity: the forces rotate with the body')
  end subroutine objectivity

  !> The explicit block kernel (no viscosity) gives the single-cell routine's forces and energy.
  subroutine block_matches_cell()
    integer, parameter :: LD = BLOCK_POINTS
    real(wp) :: x(3, 8), volume, grad(3, 8), node_volume(8), gamma(8, HOURGLASS_MODES)
    real(wp) :: u(3, 8), f(3, 3), force(3, 8), ke(24, 24), w
    real(wp) :: bu(LD, 3, 8), bv(LD, 3, 8), bgrad(LD, 3, 8), bhx(LD, 3, HOURGLASS_MODES)
    integer(i1) :: bh(LD, 8, HOURGLASS_MODES)
    real(wp) :: bk(LD, 6), visc(LD), bf(LD, 9), adj(LD, 9), det(LD), bforce(LD, 3, 8)
    real(wp) :: energy(LD), power(LD), k6(6)
    integer :: a
    call distorted_hexahedron(x)
    call hexahedron_reference(x, volume, grad, node_volume, gamma)
    call random_number(u)
    u = 0.2_wp*(u - 0.5_wp)
    k6 = [3.0_wp, 2.0_wp, 4.0_wp, 0.5_wp, -0.3_wp, 0.2_wp]
    call cell_deformation_gradient(3, 8, grad, u, f)
    call hourglass_stiffness_cell(8, grad, gamma, k6, u, f, force, ke, w)
    bu = 0.0_wp
    bv = 0.0_wp
    bgrad = 0.0_wp
    bh = 0_i1
    bhx = 0.0_wp
    do a = 1, 8                        ! the kernel's gamma = h - hX . B, hX = sum_I h_aI X_I
      bu(1, :, a) = u(:, a)
      bgrad(1, :, a) = grad(:, a)
      bh(1, a, :) = HOURGLASS_VECTORS(a, :)
      bhx(1, :, :) = bhx(1, :, :) + spread(x(:, a), 2, HOURGLASS_MODES)* &
                     spread(real(HOURGLASS_VECTORS(a, :), wp), 1, 3)
    end do
    bk = 0.0_wp
    bk(1, :) = k6
    visc = 0.0_wp
    bf = 0.0_wp
    bf(1, :) = reshape(f, [9])
    call block_adjugate(1, bf, adj, det)
    bforce = 0.0_wp
    call block_hourglass_forces(1, 8, bu, .false., bv, bgrad, bh, bhx, bk, visc, adj, det, &
                                bforce, energy, power)
    call check(maxval(abs(bforce(1, :, :) - force)) < 1e-12_wp*maxval(abs(force)), &
               'block kernel: the single-cell forces')
    call check_close(energy(1), w, 1e-12_wp, 'block kernel: the single-cell energy')
  end subroutine block_matches_cell

  pure function inverse(m) result(inv)
    real(wp), intent(in) :: m(3, 3)
    real(wp) :: inv(3, 3)
    inv(1, 1) = m(2, 2)*m(3, 3) - m(2, 3)*m(3, 2)
    inv(1, 2) = m(1, 3)*m(3, 2) - m(1, 2)*m(3, 3)
    inv(1, 3) = m(1, 2)*m(2, 3) - m(1, 3)*m(2, 2)
    inv(2, 1) = m(2, 3)*m(3, 1) - m(2, 1)*m(3, 3)
    inv(2, 2) = m(1, 1)*m(3, 3) - m(1, 3)*m(3, 1)
    inv(2, 3) = m(1, 3)*m(2, 1) - m(1, 1)*m(2, 3)
    inv(3, 1) = m(2, 1)*m(3, 2) - m(2, 2)*m(3, 1)
    inv(3, 2) = m(1, 2)*m(3, 1) - m(1, 1)*m(3, 2)
    inv(3, 3) = m(1, 1)*m(2, 2) - m(1, 2)*m(2, 1)
    inv = inv/det3(m)
  end function inverse

  pure real(wp) function det3(m)
    real(wp), intent(in) :: m(3, 3)
    det3 = m(1, 1)*(m(2, 2)*m(3, 3) - m(2, 3)*m(3, 2)) - m(1, 2)*(m(2, 1)*m(3, 3) - &
           m(2, 3)*m(3, 1)) + m(1, 3)*(m(2, 1)*m(3, 2) - m(2, 2)*m(3, 1))
  end function det3

end program test_hexahedron
