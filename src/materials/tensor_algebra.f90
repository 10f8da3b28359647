!> Small fixed-size tensor kernels for the material laws: 3x3 second-order tensors and
!> 3x3x3x3 fourth-order tangents, all pure and allocation-free.
!>
!> Conventions: a fourth-order tensor c(i,j,k,l) acts on a second-order d as
!> (c : d)_ij = sum_kl c_ijkl d_kl; (a (x) b)_ijkl = a_ij b_kl; the symmetric fourth-order
!> identity is I_ijkl = (delta_ik delta_jl + delta_il delta_jk)/2. Voigt order of symmetric
!> tensors: xx yy zz xy yz zx (no factor 2 on the shear entries).
module mefem_tensor_algebra
  use mefem_kinds, only: wp
  implicit none
  private

  public :: IDENTITY
  public :: determinant, inverse, trace, deviator, double_contraction, frobenius_norm
  public :: symmetric_to_voigt, voigt_to_symmetric, symmetric_eigenvalues
  public :: add_outer_product, add_symmetric_identity, add_symmetric_product
  public :: natural_log
  public :: inverse_cube_root, CUBE_ROOT_SERIES_RANGE, CUBE_ROOT_C1, CUBE_ROOT_C2, &
            CUBE_ROOT_C3

  !> The second-order identity.
  real(wp), parameter :: IDENTITY(3,3) = reshape([1.0_wp, 0.0_wp, 0.0_wp, &
                                                  0.0_wp, 1.0_wp, 0.0_wp, &
                                                  0.0_wp, 0.0_wp, 1.0_wp], [3, 3])

  integer, parameter :: VOIGT_ROW(6) = [1, 2, 3, 1, 2, 3]   !< Voigt entry -> row
  integer, parameter :: VOIGT_COL(6) = [1, 2, 3, 2, 3, 1]   !< Voigt entry -> column
  !> |x - 1| up to which inverse_cube_root uses its series and Newton steps (for a volume
  !> ratio: a pressure of a tenth of the bulk modulus)
  real(wp), parameter :: CUBE_ROOT_SERIES_RANGE = 0.1_wp
  !> Taylor coefficients of (1 + d)^(-1/3) (inverse_cube_root)
  real(wp), parameter :: CUBE_ROOT_C1 = -1.0_wp/3.0_wp, CUBE_ROOT_C2 = 2.0_wp/9.0_wp, &
                         CUBE_ROOT_C3 = -14.0_wp/81.0_wp
  real(wp), parameter :: ONE_THIRD = 1.0_wp/3.0_wp     !< (a product instead of a division)

contains

  !> Eigenvalues of a symmetric 3x3 tensor given in Voigt order (xx yy zz xy yz zx), largest
  !> first: the closed form of the characteristic cubic (Smith 1961), the deviator's
  !> invariants through an angle.
  pure function symmetric_eigenvalues(a) result(lambda)
    real(wp), intent(in) :: a(6)                 !< the tensor (Voigt)
    real(wp) :: lambda(3)
    real(wp), parameter :: PI = 3.14159265358979323846_wp
    real(wp) :: off, q, p, b(6), r, phi
    off = a(4)**2 + a(5)**2 + a(6)**2
    q = (a(1) + a(2) + a(3))/3.0_wp
    p = sqrt(((a(1) - q)**2 + (a(2) - q)**2 + (a(3) - q)**2 + 2.0_wp*off)/6.0_wp)
    if (p == 0.0_wp) then
      lambda = q
      return
    end if
    b = a/p
    b(1:3) = (a(1:3) - q)/p
    r = 0.5_wp*(b(1)*(b(2)*b(3) - b(5)**2) - b(4)*(b(4)*b(3) - b(5)*b(6)) + &
                b(6)*(b(4)*b(5) - b(2)*b(6)))
    r = max(-1.0_wp, min(1.0_wp, r))
    phi = acos(r)/3.0_wp
    lambda(1) = q + 2.0_wp*p*cos(phi)
    lambda(3) = q + 2.0_wp*p*cos(phi + 2.0_wp*PI/3.0_wp)
    lambda(2) = 3.0_wp*q - lambda(1) - lambda(3)
  end function symmetric_eigenvalues

  !> ln x by libm's scalar log, one value per call. The block kernels call it in their loops
  !> over points: a loop with this call is not vectorised (the function has no vector
  !> version and lives in another file), so a point's logarithm does not depend on its place
  !> in the block (libmvec's vector log differs from libm's in the last bits).
  pure real(wp) function natural_log(x)
    real(wp), intent(in) :: x        !< argument (> 0)
    natural_log = log(x)
  end function natural_log

  !> Determinant of a 3x3 matrix.
  pure real(wp) function determinant(a)
    real(wp), intent(in) :: a(3,3)   !< the matrix
    determinant = a(1,1)*(a(2,2)*a(3,3) - a(2,3)*a(3,2)) &
                - a(1,2)*(a(2,1)*a(3,3) - a(2,3)*a(3,1)) &
                + a(1,3)*(a(2,1)*a(3,2) - a(2,2)*a(3,1))
  end function determinant

  !> Inverse of a 3x3 matrix by cofactors; the caller makes sure det /= 0.
  pure subroutine inverse(a, a_inverse)
    real(wp), intent(in) :: a(3,3)            !< the matrix
    real(wp), intent(out) :: a_inverse(3,3)   !< its inverse
    real(wp) :: det
    det = determinant(a)
    a_inverse(1,1) = a(2,2)*a(3,3) - a(2,3)*a(3,2)
    a_inverse(1,2) = a(1,3)*a(3,2) - a(1,2)*a(3,3)
    a_inverse(1,3) = a(1,2)*a(2,3) - a(1,3)*a(2,2)
    a_inverse(2,1) = a(2,3)*a(3,1) - a(2,1)*a(3,3)
    a_inverse(2,2) = a(1,1)*a(3,3) - a(1,3)*a(3,1)
    a_inverse(2,3) = a(1,3)*a(2,1) - a(1,1)*a(2,3)
    a_inverse(3,1) = a(2,1)*a(3,2) - a(2,2)*a(3,1)
    a_inverse(3,2) = a(1,2)*a(3,1) - a(1,1)*a(3,2)
    a_inverse(3,3) = a(1,1)*a(2,2) - a(1,2)*a(2,1)
    a_inverse = a_inverse/det
  end subroutine inverse

  !> Trace of a 3x3 matrix.
  pure real(wp) function trace(a)
    real(wp), intent(in) :: a(3,3)   !< the matrix
    trace = a(1,1) + a(2,2) + a(3,3)
  end function trace

  !> Deviatoric part a - tr(a)/3 I.
  pure function deviator(a) result(d)
    real(wp), intent(in) :: a(3,3)   !< the tensor
    real(wp) :: d(3,3)
    real(wp) :: mean
    mean = trace(a)/3.0_wp
    d = a
    d(1,1) = d(1,1) - mean
    d(2,2) = d(2,2) - mean
    d(3,3) = d(3,3) - mean
  end function deviator

  !> Double contraction a : b = sum_ij a_ij b_ij.
  pure real(wp) function double_contraction(a, b)
    real(wp), intent(in) :: a(3,3), b(3,3)   !< the tensors
    double_contraction = sum(a*b)
  end function double_contraction

  !> Frobenius norm |a| = sqrt(a : a).
  pure real(wp) function frobenius_norm(a)
    real(wp), intent(in) :: a(3,3)   !< the tensor
    frobenius_norm = sqrt(sum(a*a))
  end function frobenius_norm

  !> Voigt vector (xx yy zz xy yz zx) of a symmetric tensor (upper triangle is read).
  pure subroutine symmetric_to_voigt(a, v)
    real(wp), intent(in) :: a(3,3)   !< symmetric tensor
    real(wp), intent(out) :: v(6)    !< its Voigt vector
    integer :: m
    do m = 1, 6
      v(m) = a(VOIGT_ROW(m), VOIGT_COL(m))
    end do
  end subroutine symmetric_to_voigt

  !> Symmetric tensor of a Voigt vector (xx yy zz xy yz zx).
  pure subroutine voigt_to_symmetric(v, a)
    real(wp), intent(in) :: v(6)       !< Voigt vector
    real(wp), intent(out) :: a(3,3)    !< symmetric tensor
    integer :: m
    do m = 1, 6
      a(VOIGT_ROW(m), VOIGT_COL(m)) = v(m)
      a(VOIGT_COL(m), VOIGT_ROW(m)) = v(m)
    end do
  end subroutine voigt_to_symmetric

  !> c = c + factor a (x) b, i.e. c_ijkl += factor a_ij b_kl.
  pure subroutine add_outer_product(c, factor, a, b)
    real(wp), intent(inout) :: c(3,3,3,3)      !< fourth-order tensor updated
    real(wp), intent(in) :: factor             !< scalar factor
    real(wp), intent(in) :: a(3,3), b(3,3)     !< the two second-order tensors
    integer :: i, j, k, l
    do l = 1, 3
      do k = 1, 3
        do j = 1, 3
          do i = 1, 3
            c(i,j,k,l) = c(i,j,k,l) + factor*a(i,j)*b(k,l)
          end do
        end do
      end do
    end do
  end subroutine add_outer_product

  !> c = c + factor I, I_ijkl = (delta_ik delta_jl + delta_il delta_jk)/2.
  pure subroutine add_symmetric_identity(c, factor)
    real(wp), intent(inout) :: c(3,3,3,3)   !< fourth-order tensor updated
    real(wp), intent(in) :: factor          !< scalar factor
    integer :: i, j
    do j = 1, 3
      do i = 1, 3
        c(i,j,i,j) = c(i,j,i,j) + 0.5_wp*factor
        c(i,j,j,i) = c(i,j,j,i) + 0.5_wp*factor
      end do
    end do
  end subroutine add_symmetric_identity

  !> c = c + factor/2 (a_ik b_jl + a_il b_jk): the tangent of d -> factor a d b^T
  !> symmetrised in kl (for symmetric a = b it is the Lie derivative term of b d b).
  pure subroutine add_symmetric_product(c, factor, a, b)
    real(wp), intent(inout) :: c(3,3,3,3)      !< fourth-order tensor updated
    real(wp), intent(in) :: factor             !< scalar factor
    real(wp), intent(in) :: a(3,3), b(3,3)     !< the two second-order tensors
    integer :: i, j, k, l
    do l = 1, 3
      do k = 1, 3
        do j = 1, 3
          do i = 1, 3
            c(i,j,k,l) = c(i,j,k,l) + 0.5_wp*factor*(a(i,k)*b(j,l) + a(i,l)*b(j,k))
          end do
        end do
      end do
    end do
  end subroutine add_symmetric_product


  !> x^(-1/3) for x > 0. The volume ratio J of a metal (elastic volume change only) is
  !> within CUBE_ROOT_SERIES_RANGE of 1 up to a pressure of a tenth of the bulk modulus:
  !> there the Taylor polynomial of (1 + d)^(-1/3) to d^3 (relative error about
  !> 35/243 d^4 < 1.5e-5) and two Newton steps y (4 - x y^3)/3 (each takes a relative error e
  !> to about 2 e^2: 5e-10, then below 1e-18) give the value to a few ulp, a fraction of the
  !> cost of **; other x use **.
  pure real(wp) function inverse_cube_root(x) result(y)
    real(wp), intent(in) :: x           !< positive argument
    real(wp) :: d
    d = x - 1.0_wp
    if (abs(d) <= CUBE_ROOT_SERIES_RANGE) then
      y = 1.0_wp + d*(CUBE_ROOT_C1 + d*(CUBE_ROOT_C2 + d*CUBE_ROOT_C3))
      y = y*(4.0_wp - x*(y*y*y))*ONE_THIRD
      y = y*(4.0_wp - x*(y*y*y))*ONE_THIRD
    else
      y = x**(-1.0_wp/3.0_wp)
    end if
  end function inverse_cube_root

end module mefem_tensor_algebra
