!> Material fixtures shared by the unit tests (steel for the J2 laws, a rubber for
!> Mooney-Rivlin): MPa, mm, tonne, as in the decks of input/.
module mefem_test_fixtures
  use mefem_kinds, only: wp
  use mefem_model, only: material_t, MAT_ELASTIC, MAT_PIECEWISE_LINEAR, MAT_POWER_LAW, &
                         MAT_JOHNSON_COOK, &
                         MAT_MOONEY_RIVLIN
  implicit none
  private

  public :: linear_steel, power_law_steel, table_steel, curve_steel, elastic_steel, rubber
  public :: johnson_cook_steel

contains

  !> *MAT_024 with SIGY and ETAN (MPa, mm, t).
  type(material_t) function linear_steel() result(mat)
    mat%id = 1
    mat%kind = MAT_PIECEWISE_LINEAR
    mat%density = 7.85e-9_wp
    mat%young = 210000.0_wp
    mat%poisson = 0.3_wp
    mat%yield_stress = 250.0_wp
    mat%tangent_modulus = 2000.0_wp
  end function linear_steel

  !> *MAT_018 with K, N and SIGY.
  type(material_t) function power_law_steel() result(mat)
    mat%id = 2
    mat%kind = MAT_POWER_LAW
    mat%density = 7.85e-9_wp
    mat%young = 210000.0_wp
    mat%poisson = 0.3_wp
    mat%k_strength = 530.0_wp
    mat%n_exponent = 0.26_wp
    mat%yield_stress = 250.0_wp
  end function power_law_steel

  !> *MAT_015 with A = 300 MPa, B = 0, N = 1, EPSO = 1 /s (no thermal or failure terms).
  type(material_t) function johnson_cook_steel() result(mat)
    mat%id = 15
    mat%kind = MAT_JOHNSON_COOK
    mat%density = 7.85e-9_wp
    mat%young = 200000.0_wp
    mat%poisson = 0.3_wp
    mat%jc_a = 300.0_wp
    mat%n_exponent = 1.0_wp
    mat%reference_rate = 1.0_wp
  end function johnson_cook_steel

  !> *MAT_024 with an EPS/ES table.
  type(material_t) function table_steel() result(mat)
    mat = linear_steel()
    mat%id = 3
    mat%n_points = 4
    mat%eps(1:4) = [0.0_wp, 0.05_wp, 0.2_wp, 0.5_wp]
    mat%es(1:4) = [250.0_wp, 300.0_wp, 350.0_wp, 380.0_wp]
  end function table_steel

  !> *MAT_024 with LCSS (curve 1 of `curves`).
  type(material_t) function curve_steel() result(mat)
    mat = linear_steel()
    mat%id = 4
    mat%lcss = 11
    mat%lcss_curve = 1
  end function curve_steel

  !> *MAT_ELASTIC.
  type(material_t) function elastic_steel() result(mat)
    mat%id = 5
    mat%kind = MAT_ELASTIC
    mat%density = 7.85e-9_wp
    mat%young = 210000.0_wp
    mat%poisson = 0.3_wp
  end function elastic_steel

  !> *MAT_027 (B = 0: neo-Hookean), E stored as the reader does.
  type(material_t) function rubber(a, b) result(mat)
    real(wp), intent(in) :: a, b
    mat%id = 6
    mat%kind = MAT_MOONEY_RIVLIN
    mat%density = 1.1e-9_wp
    mat%poisson = 0.49_wp
    mat%mr_a = a
    mat%mr_b = b
    mat%young = 4.0_wp*(a + b)*(1.0_wp + mat%poisson)
  end function rubber

end module mefem_test_fixtures
