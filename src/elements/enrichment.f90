!> The constants the ME-FEM elements take from the GMF approximation on the reference simplex.
!>
!> The enriched node sits at the centroid, so inside an element Psi_I = N_I - Psi_e/(dim+1)
!> for the corners (N_I linear) and only the enrichment function Psi_e is needed. It is
!> evaluated once per run (and support size) on the reference simplex of unit edge (equilateral
!> triangle / regular tetrahedron), and from it come:
!> - kappa: at the integration point of side m (edge midpoint / face centroid),
!>   grad Psi_e = ((dim+1) kappa / H_m) n_m, n_m the inward unit normal, H_m the altitude;
!>   obtained as the limit of the GMF gradient approaching the side along the median
!>   (Richardson extrapolation of two points; the error is linear in the distance);
!> - mass_fraction: the mean of Psi_e over the element (lumped mass m_e = rho V psibar);
!> - centroid_value: Psi_e at the centroid (for output of the centroid displacement);
!> - bubble_mass_ratio: the explicit solver's lumped inertia of the bubble dof over rho V, by
!>   default dim kappa^2, the value that gives the bubble of a regular element the same
!>   frequency bound as its corners (doc/theory.md 7), or the deck's *MEFEM_ENRICHMENT BMASS.
!> Nothing here is taken from tables; the tables of the reference are the tests' oracles.
module mefem_enrichment
  use mefem_kinds, only: wp
  use mefem_errors, only: status_t
  use mefem_strings, only: rtoa
  use mefem_gmf, only: gmf_shape, GMF_ATAN, GMF_EXP
  implicit none
  private

  public :: enrichment_setup, reference_simplex, gauss_legendre

  !> Enrichment constants for one dimension, basis and support size.
  type, public :: enrichment_t
    integer :: dim = 0                      !< 2 (triangle) or 3 (tetrahedron)
    integer :: basis = GMF_ATAN             !< GMF_ATAN or GMF_EXP
    real(wp) :: support_ratio = 1.5_wp      !< a / L (support radius over edge length)
    real(wp) :: kappa = 0.0_wp              !< side slope constant
    real(wp) :: mass_fraction = 0.0_wp      !< mean of Psi_e over the element
    real(wp) :: centroid_value = 0.0_wp     !< Psi_e at the centroid
    real(wp) :: bubble_mass_ratio = 0.0_wp  !< explicit: inertia of a bubble dof / (rho V)
  end type enrichment_t

  integer, parameter :: QUADRATURE_POINTS = 20   !< Gauss points per direction (collapsed rule)

contains

  !> Corners and centroid (last column) of the unit-edge reference simplex of dimension dim.
  pure subroutine reference_simplex(dim, xn)
    integer, intent(in) :: dim              !< 2 or 3
    real(wp), intent(out) :: xn(dim, dim+2) !< corners 1..dim+1, centroid dim+2
    if (dim == 2) then
      xn(:, 1) = [0.0_wp, 0.0_wp]
      xn(:, 2) = [1.0_wp, 0.0_wp]
      xn(:, 3) = [0.5_wp, sqrt(3.0_wp)/2.0_wp]
    else
      xn(:, 1) = [0.0_wp, 0.0_wp, 0.0_wp]
      xn(:, 2) = [1.0_wp, 0.0_wp, 0.0_wp]
      xn(:, 3) = [0.5_wp, sqrt(3.0_wp)/2.0_wp, 0.0_wp]
      xn(:, 4) = [0.5_wp, sqrt(3.0_wp)/6.0_wp, sqrt(2.0_wp/3.0_wp)]
    end if
    xn(:, dim+2) = sum(xn(:, 1:dim+1), dim=2)/real(dim + 1, wp)
  end subroutine reference_simplex

  !> Compute the enrichment constants; status fails if the GMF cannot be solved (a/L <= 1).
  subroutine enrichment_setup(dim, basis, support_ratio, bubble_mass, en, status)
    integer, intent(in) :: dim                !< 2 or 3
    integer, intent(in) :: basis              !< GMF_ATAN or GMF_EXP
    real(wp), intent(in) :: support_ratio     !< a/L
    real(wp), intent(in) :: bubble_mass       !< bubble inertia / (rho V); 0: dim kappa^2
    type(enrichment_t), intent(out) :: en     !< the constants
    type(status_t), intent(out) :: status     !< failure and reason
    real(wp) :: xn(dim, dim+2), psi(dim+2), dpsi(dim, dim+2), side_point(dim), normal(dim)
    real(wp) :: altitude, k1, k2, t
    logical :: ok1, ok2, ok3
    en%dim = dim
    en%basis = basis
    en%support_ratio = support_ratio
    if (support_ratio <= 1.0_wp) then
      status%ok = .false.
      status%message = 'the GMF support a/L = '//rtoa(support_ratio)// &
          ' must exceed 1 so that every node covers the element'
      return
    end if
    call reference_simplex(dim, xn)
    ! side opposite the last corner: edge 1-2 (2D) / face 1-2-3 (3D), inward normal +y / +z
    side_point = sum(xn(:, 1:dim), dim=2)/real(dim, wp)
    normal = 0.0_wp
    normal(dim) = 1.0_wp
    altitude = xn(dim, dim+1)
    t = 1.0e-6_wp
    call gmf_shape(basis, support_ratio, xn, side_point + t*(xn(:, dim+2) - side_point), psi, &
                   dpsi, ok1)
    k1 = dot_product(dpsi(:, dim+2), normal)*altitude/real(dim + 1, wp)
    call gmf_shape(basis, support_ratio, xn, side_point + 0.25_wp*t*(xn(:, dim+2) - side_point), &
                   psi, dpsi, ok2)
    k2 = dot_product(dpsi(:, dim+2), normal)*altitude/real(dim + 1, wp)
    en%kappa = (4.0_wp*k2 - k1)/3.0_wp
    call gmf_shape(basis, support_ratio, xn, xn(:, dim+2), psi, dpsi, ok3)
    en%centroid_value = psi(dim+2)
    en%mass_fraction = mean_enrichment(dim, basis, support_ratio, xn, status)
    if (bubble_mass > 0.0_wp) then
      en%bubble_mass_ratio = bubble_mass
    else
      en%bubble_mass_ratio = real(dim, wp)*en%kappa**2
    end if
    if (.not. (ok1 .and. ok2 .and. ok3)) then
      status%ok = .false.
      status%message = 'the GMF approximation did not converge on the reference element'
    end if
  end subroutine enrichment_setup

  !> Mean of Psi_e over the reference simplex: collapsed (Duffy) Gauss-Legendre rule, whose
  !> points are all interior (the GMF is singular in lambda on the boundary).
  function mean_enrichment(dim, basis, support_ratio, xn, status) result(mean)
    integer, intent(in) :: dim, basis               !< dimension, basis
    real(wp), intent(in) :: support_ratio           !< a/L
    real(wp), intent(in) :: xn(:,:)                 !< reference nodes
    type(status_t), intent(inout) :: status         !< failure and reason
    real(wp) :: mean
    real(wp) :: gp(QUADRATURE_POINTS), gw(QUADRATURE_POINTS), u, v, w, jac, x(dim), total
    real(wp) :: psi(dim+2), dpsi(dim, dim+2), volume, nearest_side
    integer :: i, j, k, nk
    logical :: ok
    call gauss_legendre(QUADRATURE_POINTS, gp, gw)
    total = 0.0_wp
    volume = 0.0_wp
    nk = 1
    w = 0.0_wp
    if (dim == 3) nk = QUADRATURE_POINTS
    do i = 1, QUADRATURE_POINTS
      do j = 1, QUADRATURE_POINTS
        do k = 1, nk
          ! (u, v, w) in the unit cube -> barycentric-type coordinates of the simplex
          u = gp(i)
          v = gp(j)*(1.0_wp - u)
          if (dim == 2) then
            jac = (1.0_wp - u)*gw(i)*gw(j)
            x = xn(:, 1) + u*(xn(:, 2) - xn(:, 1)) + v*(xn(:, 3) - xn(:, 1))
          else
            w = gp(k)*(1.0_wp - u - v)
            jac = (1.0_wp - u)*(1.0_wp - u - v)*gw(i)*gw(j)*gw(k)
            x = xn(:, 1) + u*(xn(:, 2) - xn(:, 1)) + v*(xn(:, 3) - xn(:, 1)) &
                + w*(xn(:, 4) - xn(:, 1))
          end if
          call gmf_shape(basis, support_ratio, xn, x, psi, dpsi, ok)
          ! within round-off of a side lambda is unbounded and Newton stalls; there Psi_e is
          ! below 1e-3 and the point's weight negligible, so the last iterate is kept
          if (dim == 2) then
            nearest_side = min(u, v, 1.0_wp - u - v)
          else
            nearest_side = min(u, v, w, 1.0_wp - u - v - w)
          end if
          if (.not. ok .and. nearest_side > 1.0e-3_wp) then
            status%ok = .false.
            status%message = 'the GMF approximation did not converge inside the reference element'
          end if
          total = total + jac*psi(dim+2)
          volume = volume + jac
        end do
      end do
    end do
    mean = total/volume
  end function mean_enrichment

  !> Gauss-Legendre points and weights on [0, 1] (Newton on the Legendre polynomial).
  pure subroutine gauss_legendre(n, points, weights)
    integer, intent(in) :: n                  !< number of points
    real(wp), intent(out) :: points(n)        !< abscissas in (0, 1)
    real(wp), intent(out) :: weights(n)       !< weights, summing to 1
    real(wp), parameter :: PI = 4.0_wp*atan(1.0_wp)
    real(wp) :: z, p0, p1, p2, dp, dz
    integer :: i, k, it
    do i = 1, n
      z = cos(PI*(real(i, wp) - 0.25_wp)/(real(n, wp) + 0.5_wp))
      do it = 1, 100
        p0 = 1.0_wp
        p1 = z
        do k = 2, n
          p2 = ((2*k - 1)*z*p1 - (k - 1)*p0)/real(k, wp)
          p0 = p1
          p1 = p2
        end do
        dp = n*(z*p1 - p0)/(z*z - 1.0_wp)
        dz = p1/dp
        z = z - dz
        if (abs(dz) < 1.0e-15_wp) exit
      end do
      points(i) = 0.5_wp*(1.0_wp - z)
      weights(i) = 1.0_wp/((1.0_wp - z*z)*dp*dp)
    end do
  end subroutine gauss_legendre

end module mefem_enrichment
