!> Finite-strain cell kernels: the tangent is the derivative of the internal force (central
!> differences), a rigid rotation produces no force, and the small-strain limit is the linear
!> stiffness. The material is a compressible neo-Hookean law written here (tau = mu (b - I) +
!> lambda ln J I, c = lambda 1(x)1 + 2 (mu - lambda ln J) I_sym), so the test checks the element
!> kernels independently of the material library.
program test_cell_finite_strain
  use mefem_kinds, only: wp
  use mefem_testing, only: test_start, test_finish, check, check_close
  use mefem_strings, only: rtoa
  use mefem_cell_finite_strain, only: cell_deformation_gradient, cell_internal_force, &
                                      cell_tangent, inverse_3x3
  use mefem_cell_linear, only: cell_stiffness
  implicit none

  real(wp), parameter :: MU = 3.0_wp, LAMBDA = 7.0_wp

  call test_start('cell_finite_strain')
  call tangent_vs_differences(2, 6)
  call tangent_vs_differences(3, 7)
  call rigid_rotation(3, 7)
  call small_strain_limit(2, 6)
  call small_strain_limit(3, 5)
  call test_finish()

contains

  !> Neo-Hookean Kirchhoff stress and its spatial tangent.
  subroutine neo_hooke(f, tau, c)
    real(wp), intent(in) :: f(3, 3)
    real(wp), intent(out) :: tau(3, 3), c(3, 3, 3, 3)
    real(wp) :: b(3, 3), finv(3, 3), det, eye(3, 3)
    integer :: i, j, k, l
    eye = 0.0_wp
    do i = 1, 3
      eye(i, i) = 1.0_wp
    end do
    call inverse_3x3(f, finv, det)
    b = matmul(f, transpose(f))
    tau = MU*(b - eye) + LAMBDA*log(det)*eye
    do l = 1, 3
      do k = 1, 3
        do j = 1, 3
          do i = 1, 3
            c(i, j, k, l) = LAMBDA*eye(i, j)*eye(k, l) + (MU - LAMBDA*log(det))* &
                            (eye(i, k)*eye(j, l) + eye(i, l)*eye(j, k))
          end do
        end do
      end do
    end do
  end subroutine neo_hooke

  !> Random gradients of a cell that sum to zero (as every consistent cell's do).
  subroutine random_cell(dim, nn, grad)
    integer, intent(in) :: dim, nn
    real(wp), intent(out) :: grad(dim, nn)
    call random_number(grad)
    grad = grad - 0.5_wp
    grad(:, nn) = -sum(grad(:, 1:nn-1), dim=2)
  end subroutine random_cell

  !> Force of a cell for displacements u.
  subroutine cell_force(dim, nn, grad, u, force)
    integer, intent(in) :: dim, nn
    real(wp), intent(in) :: grad(dim, nn), u(dim, nn)
    real(wp), intent(out) :: force(dim, nn)
    real(wp) :: f(3, 3), tau(3, 3), c(3, 3, 3, 3)
    call cell_deformation_gradient(dim, nn, grad, u, f)
    call neo_hooke(f, tau, c)
    call cell_internal_force(dim, nn, grad, 0.7_wp, f, tau, force)
  end subroutine cell_force

  subroutine tangent_vs_differences(dim, nn)
    integer, intent(in) :: dim, nn
    real(wp) :: grad(dim, nn), u(dim, nn), up(dim, nn), fp(dim, nn), fm(dim, nn)
    real(wp) :: f(3, 3), tau(3, 3), c(3, 3, 3, 3), ke(dim*nn, dim*nn), fd(dim*nn, dim*nn)
    real(wp), parameter :: H = 1.0e-6_wp
    integer :: a, i
    call random_cell(dim, nn, grad)
    call random_number(u)
    u = 0.3_wp*(u - 0.5_wp)                 ! finite strains of order 0.1-0.3
    call cell_deformation_gradient(dim, nn, grad, u, f)
    call neo_hooke(f, tau, c)
    call cell_tangent(dim, nn, grad, 0.7_wp, f, tau, c, ke)
    do a = 1, nn
      do i = 1, dim
        up = u
        up(i, a) = u(i, a) + H
        call cell_force(dim, nn, grad, up, fp)
        up(i, a) = u(i, a) - H
        call cell_force(dim, nn, grad, up, fm)
        fd(:, dim*(a-1) + i) = reshape((fp - fm)/(2.0_wp*H), [dim*nn])
      end do
    end do
    ! central differences with h = 1e-6: truncation ~1e-12, round-off ~1e-10 relative
    call check(maxval(abs(ke - fd)) < 1.0e-6_wp*maxval(abs(ke)), &
        itoa_dim(dim)//': tangent = derivative of the internal force', &
        rtoa(maxval(abs(ke - fd))/maxval(abs(ke))))
    call check(maxval(abs(ke - transpose(ke))) < 1.0e-12_wp*maxval(abs(ke)), &
        itoa_dim(dim)//': tangent symmetric (hyperelastic material)')
  end subroutine tangent_vs_differences

  subroutine rigid_rotation(dim, nn)
    integer, intent(in) :: dim, nn
    real(wp) :: grad(dim, nn), x(dim, nn), u(dim, nn), force(dim, nn), q(3, 3), t
    integer :: a
    call random_cell(dim, nn, grad)
    t = 0.8_wp
    q = reshape([cos(t), sin(t), 0.0_wp, -sin(t), cos(t), 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [3, 3])
    call positions_for(dim, nn, grad, x)
    do a = 1, nn
      u(:, a) = matmul(q(1:dim, 1:dim), x(:, a)) - x(:, a)
    end do
    call cell_force(dim, nn, grad, u, force)
    call check(maxval(abs(force)) < 1.0e-12_wp, itoa_dim(dim)// &
        ': a rigid rotation of 46 degrees produces no force', rtoa(maxval(abs(force))))
  end subroutine rigid_rotation

  !> Node positions x with sum_I x_I (x) G_I = I: x = (G G^T)^-1 G.
  subroutine positions_for(dim, nn, grad, x)
    integer, intent(in) :: dim, nn
    real(wp), intent(in) :: grad(dim, nn)
    real(wp), intent(out) :: x(dim, nn)
    real(wp) :: full(3, 3), inv(3, 3), det
    full = 0.0_wp
    full(1:dim, 1:dim) = matmul(grad, transpose(grad))
    if (dim == 2) full(3, 3) = 1.0_wp
    call inverse_3x3(full, inv, det)
    x = matmul(inv(1:dim, 1:dim), grad)
  end subroutine positions_for

  subroutine small_strain_limit(dim, nn)
    integer, intent(in) :: dim, nn
    real(wp) :: grad(dim, nn), u(dim, nn), f(3, 3), tau(3, 3), c(3, 3, 3, 3)
    real(wp) :: ke(dim*nn, dim*nn), kl(dim*nn, dim*nn)
    call random_cell(dim, nn, grad)
    u = 0.0_wp
    call cell_deformation_gradient(dim, nn, grad, u, f)
    call neo_hooke(f, tau, c)
    call cell_tangent(dim, nn, grad, 0.7_wp, f, tau, c, ke)
    call cell_stiffness(dim, nn, grad, 0.7_wp, LAMBDA, MU, kl)
    call check_close(reshape(ke, [size(ke)]), reshape(kl, [size(kl)]), 1.0e-13_wp, &
        itoa_dim(dim)//': tangent at F = I equals the linear stiffness', atol=1.0e-13_wp)
  end subroutine small_strain_limit

  function itoa_dim(dim) result(s)
    integer, intent(in) :: dim
    character(len=2) :: s
    write(s, '(i1,a)') dim, 'D'
  end function itoa_dim

end program test_cell_finite_strain
