!> The generalized meshfree (GMF) convex approximation of Wu, Park & Chen (2011), used by the
!> meshfree-enriched elements (theory: doc/theory.md, "GMF approximation").
!>
!>   Psi_I(x) = phi_a(x - x_I) G(lambda . (x - x_I)) / sum_J phi_a(x - x_J) G(lambda . (x - x_J))
!>
!> with the cubic B-spline window phi_a of circular/spherical support radius a, a basis function
!> G (GMF(atan): G(z) = pi/2 + atan(z), evaluated as atan2(1, -z); or G = exp, max-entropy-like)
!> and lambda(x) solving the linear reproduction condition R = sum_I Psi_I (x - x_I) = 0 by a
!> trust-region Newton method (plain Newton diverges for atan near the boundary). Gradients
!> use the closed form obtained by differentiating R(lambda(x), x) = 0.
module mefem_gmf
  use mefem_kinds, only: wp
  implicit none
  private

  integer, parameter, public :: GMF_ATAN = 1   !< G(z) = pi/2 + atan(z)
  integer, parameter, public :: GMF_EXP = 2    !< G(z) = exp(z)
  integer, parameter, public :: GMF_MAX_NODES = 16

  public :: gmf_shape, cubic_spline

  real(wp), parameter :: RESIDUAL_TOL = 1.0e-14_wp   !< |R| tolerance relative to a
  !> accepted when the trust region collapses at the round-off floor (points very near a side)
  real(wp), parameter :: STALLED_TOL = 1.0e-10_wp
  integer, parameter :: MAX_ITERATIONS = 200

contains

  !> Cubic B-spline window phi(z) and dphi/dz, z = r/a (normalisation irrelevant).
  pure subroutine cubic_spline(z, phi, dphi)
    real(wp), intent(in) :: z      !< normalised distance r/a (>= 0)
    real(wp), intent(out) :: phi   !< window value
    real(wp), intent(out) :: dphi  !< derivative with respect to z
    if (z <= 0.5_wp) then
      phi = 2.0_wp/3.0_wp - 4.0_wp*z**2 + 4.0_wp*z**3
      dphi = -8.0_wp*z + 12.0_wp*z**2
    else if (z <= 1.0_wp) then
      phi = 4.0_wp/3.0_wp - 4.0_wp*z + 4.0_wp*z**2 - 4.0_wp/3.0_wp*z**3
      dphi = -4.0_wp + 8.0_wp*z - 4.0_wp*z**2
    else
      phi = 0.0_wp
      dphi = 0.0_wp
    end if
  end subroutine cubic_spline

  !> Basis G(z) and g = G'(z)/G(z).
  pure subroutine basis(kind, z, zshift, g_value, g_ratio)
    integer, intent(in) :: kind        !< GMF_ATAN or GMF_EXP
    real(wp), intent(in) :: z          !< argument lambda . d
    real(wp), intent(in) :: zshift     !< exp only: subtracted to avoid overflow (cancels)
    real(wp), intent(out) :: g_value   !< G(z) (scaled for exp)
    real(wp), intent(out) :: g_ratio   !< G'(z)/G(z)
    if (kind == GMF_EXP) then
      g_value = exp(z - zshift)
      g_ratio = 1.0_wp
    else
      g_value = atan2(1.0_wp, -z)
      g_ratio = 1.0_wp/((1.0_wp + z*z)*g_value)
    end if
  end subroutine basis

  !> Shape functions and gradients of the GMF approximation at x for nodes xn.
  !> converged is false when the reproduction condition could not be solved (x outside the
  !> convex hull of the nodes whose support covers it).
  pure subroutine gmf_shape(kind, a, xn, x, psi, dpsi, converged)
    integer, intent(in) :: kind              !< GMF_ATAN or GMF_EXP
    real(wp), intent(in) :: a                !< support radius (same for all nodes)
    real(wp), intent(in) :: xn(:,:)          !< (dim, np) node positions
    real(wp), intent(in) :: x(:)             !< (dim) evaluation point
    real(wp), intent(out) :: psi(:)          !< (np) shape functions
    real(wp), intent(out) :: dpsi(:,:)       !< (dim, np) gradients
    logical, intent(out) :: converged        !< lambda found
    integer :: dim, np, i, it
    real(wp) :: d(size(x), size(psi)), phi(size(psi)), gphi(size(x), size(psi))
    real(wp) :: gv(size(psi)), gr(size(psi))
    real(wp) :: lambda(size(x)), trial(size(x)), step(size(x)), r(size(x)), rtrial(size(x))
    real(wp) :: amat(size(x), size(x)), drdx(size(x), size(x)), dlambda(size(x), size(x))
    real(wp) :: c(size(x), size(psi)), csum(size(x)), radius, dphi, tau, tau_floor, s
    real(wp) :: beta(size(x))
    integer :: j
    dim = size(x)
    np = size(psi)
    do i = 1, np
      d(:, i) = x - xn(:, i)
      radius = norm2(d(:, i))
      call cubic_spline(radius/a, phi(i), dphi)
      if (radius > 0.0_wp) then
        gphi(:, i) = dphi/a*d(:, i)/radius
      else
        gphi(:, i) = 0.0_wp
      end if
    end do
    ! trust-region Newton on the reproduction condition R(lambda) = 0
    lambda = 0.0_wp
    call evaluate(lambda, psi, r, gv, gr, s)
    tau = 4.0_wp/a
    converged = .false.
    do it = 1, MAX_ITERATIONS
      if (norm2(r) < RESIDUAL_TOL*a) then
        converged = .true.
        exit
      end if
      call jacobian(psi, gr, r, amat)
      call solve_small(amat, -r, step, dim)
      tau_floor = 1.0e-15_wp*max(norm2(lambda), 1.0_wp/a)
      if (norm2(step) > tau) step = step*(tau/norm2(step))
      do
        trial = lambda + step
        call evaluate(trial, psi, rtrial, gv, gr, s)
        if (norm2(rtrial) < norm2(r)) exit
        tau = 0.25_wp*min(tau, norm2(step))
        step = step*(tau/norm2(step))
        if (tau < tau_floor) exit
      end do
      if (tau < tau_floor) exit     ! stalled: no step of relative size 1e-15 reduces R
      lambda = trial
      r = rtrial
      tau = 2.0_wp*tau
    end do
    call evaluate(lambda, psi, r, gv, gr, s)
    if (.not. converged) converged = norm2(r) < STALLED_TOL*a
    if (.not. converged) then
      dpsi = 0.0_wp
      return
    end if
    ! gradients: grad lambda from dR/dx = 0, then grad Psi_I = c_I - Psi_I sum_K c_K
    call jacobian(psi, gr, r, amat)
    drdx = 0.0_wp
    do i = 1, dim
      drdx(i, i) = 1.0_wp
    end do
    do i = 1, np
      beta = gv(i)*gphi(:, i)/s + psi(i)*gr(i)*lambda
      do j = 1, dim
        drdx(:, j) = drdx(:, j) + d(:, i)*beta(j)
      end do
    end do
    do i = 1, dim
      call solve_small(amat, -drdx(:, i), dlambda(:, i), dim)
    end do
    do i = 1, np
      c(:, i) = gv(i)*gphi(:, i)/s + psi(i)*gr(i)*(lambda + matmul(d(:, i), dlambda))
    end do
    csum = sum(c, dim=2)
    do i = 1, np
      dpsi(:, i) = c(:, i) - psi(i)*csum
    end do

  contains

    !> Psi, R, G values and ratios for a given lambda.
    pure subroutine evaluate(lam, psi_out, r_out, g_out, ratio_out, s_out)
      real(wp), intent(in) :: lam(:)
      real(wp), intent(out) :: psi_out(:), r_out(:), g_out(:), ratio_out(:), s_out
      real(wp) :: z(size(psi_out)), zshift
      integer :: k
      do k = 1, size(psi_out)
        z(k) = dot_product(lam, d(:, k))
      end do
      zshift = 0.0_wp
      if (kind == GMF_EXP) zshift = maxval(z, mask=phi > 0.0_wp)
      do k = 1, size(psi_out)
        call basis(kind, z(k), zshift, g_out(k), ratio_out(k))
      end do
      s_out = sum(phi*g_out)
      psi_out = phi*g_out/s_out
      r_out = matmul(d, psi_out)
    end subroutine evaluate

    !> A = dR/dlambda = sum Psi g d d^T - R (sum Psi g d)^T.
    pure subroutine jacobian(psi_in, ratio_in, r_in, a_out)
      real(wp), intent(in) :: psi_in(:), ratio_in(:), r_in(:)
      real(wp), intent(out) :: a_out(:,:)
      real(wp) :: w(size(r_in))
      integer :: k, l
      a_out = 0.0_wp
      w = 0.0_wp
      do k = 1, size(psi_in)
        do l = 1, size(r_in)
          a_out(:, l) = a_out(:, l) + psi_in(k)*ratio_in(k)*d(:, k)*d(l, k)
        end do
        w = w + psi_in(k)*ratio_in(k)*d(:, k)
      end do
      do l = 1, size(r_in)
        a_out(:, l) = a_out(:, l) - r_in*w(l)
      end do
    end subroutine jacobian

  end subroutine gmf_shape

  !> Solve the small dense system m y = b (dim 2 or 3) by Gaussian elimination with pivoting.
  pure subroutine solve_small(m, b, y, n)
    integer, intent(in) :: n            !< size
    real(wp), intent(in) :: m(n, n)     !< matrix
    real(wp), intent(in) :: b(n)        !< right-hand side
    real(wp), intent(out) :: y(n)       !< solution
    real(wp) :: w(n, n + 1), t(n + 1)
    integer :: i, k, p
    w(:, 1:n) = m
    w(:, n + 1) = b
    do k = 1, n
      p = k - 1 + maxloc(abs(w(k:n, k)), dim=1)
      if (p /= k) then
        t = w(k, :)
        w(k, :) = w(p, :)
        w(p, :) = t
      end if
      if (w(k, k) == 0.0_wp) then
        y = 0.0_wp
        return
      end if
      do i = k + 1, n
        w(i, k:n+1) = w(i, k:n+1) - w(i, k)/w(k, k)*w(k, k:n+1)
      end do
    end do
    do k = n, 1, -1
      y(k) = (w(k, n + 1) - dot_product(w(k, k+1:n), y(k+1:n)))/w(k, k)
    end do
  end subroutine solve_small

end module mefem_gmf
