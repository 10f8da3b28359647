!> Lumped (diagonal) nodal masses of the deformable elements, mesh and enriched nodes alike.
!>
!> The ME-FEM element is P1 plus a bubble in hierarchical form (mefem_cells): u = sum N_I u_I
!> + Psi_e b_e. Per ME-FEM element of volume V (area with unit thickness in 2D), density rho:
!> - each corner rho V/(dim+1), the integral of rho N_I: the corners carry the whole mass, so
!>   translation, total mass and momentum are exact whatever the bubble's mass;
!> - the enriched node (bubble amplitude b_e), two uses:
!>   inertia (explicit solver): rho V bubble_mass_ratio (default dim kappa^2, doc/theory.md
!>   7: the bubble of a regular element then has the frequency bound of its corners; the
!>   bubble carries no translation, so its inertia is free to choose: selective mass);
!>   load (body loads of the static analyses): rho V psibar, the integral of rho Psi_e
!>   (psibar = enrichment_t%mass_fraction), the consistent load on b_e.
!> A standard linear element gives rho V/(dim+1) per corner, a hexahedron rho int N_I dV per
!> corner (rho V/8 when it is a parallelepiped). Nodes of rigid parts only get no
!> mass here (rigid bodies carry their own). The masses of *ELEMENT_MASS and
!> *ELEMENT_MASS_PART (model%nodes%added_mass) are added at their mesh nodes, rigid parts'
!> too (a rigid body takes the masses at its nodes as point masses). Every rank computes all masses from the global
!> model, elements in ascending order, so the values are the same bits on every rank and for
!> any number of ranks; a rank takes its share as mass(layout%node_global).
module mefem_lumped_mass
  use mefem_kinds, only: wp
  use mefem_vector_math, only: cross
  use mefem_model, only: model_t
  use mefem_cells, only: cells_t
  implicit none
  private

  public :: lumped_mass, simplex_measure

contains

  !> Lumped mass of every node: mesh nodes 1..n_mesh_nodes, then the enriched nodes (their
  !> inertia, or the mass their body load acts on).
  subroutine lumped_mass(model, cells, inertia, mass)
    type(model_t), intent(in) :: model                 !< resolved model (densities, geometry)
    type(cells_t), intent(in) :: cells                 !< cells built from the same model
    logical, intent(in) :: inertia                     !< enriched nodes: inertia, else load
    real(wp), allocatable, intent(out) :: mass(:)      !< (n_mesh_nodes + n_enriched) masses
    integer, allocatable :: standard_cell(:)
    real(wp) :: rho, volume, bubble, corner_share
    integer :: nv, e, c, material, h, nn

    nv = cells%dim + 1
    allocate(mass(cells%n_mesh_nodes + cells%n_enriched))
    mass = 0.0_wp
    ! standard elements are their own cell: find it (element -> cell)
    allocate(standard_cell(model%elements%n))
    standard_cell = 0
    do c = 1, cells%n
      if (cells%enriched_of(cells%elements(1, c)) == 0) standard_cell(cells%elements(1, c)) = c
    end do
    bubble = merge(cells%enrichment%bubble_mass_ratio, cells%enrichment%mass_fraction, inertia)

    do e = 1, model%elements%n
      if (cells%enriched_of(e) > 0) then
        material = model%parts(model%elements%part(e))%material
        rho = model%materials(material)%density
        volume = simplex_measure(cells%dim, model%nodes%x(:, model%elements%conn(1:nv, e)))
        corner_share = rho*volume/real(nv, wp)
        mass(model%elements%conn(1:nv, e)) = mass(model%elements%conn(1:nv, e)) + corner_share
        mass(cells%enriched_of(e)) = mass(cells%enriched_of(e)) + rho*volume*bubble
      else if (standard_cell(e) > 0) then
        c = standard_cell(e)
        rho = model%materials(cells%material(c))%density
        h = cells%hex_of(c)
        if (h > 0) then           ! hexahedron: rho int N_I dV (the consistent mass' row sums)
          nn = cells%nnodes(c)
          mass(cells%nodes(1:nn, c)) = mass(cells%nodes(1:nn, c)) + &
                                       rho*cells%node_volume(1:nn, h)
        else
          corner_share = rho*cells%weight(c)/real(nv, wp)
          mass(cells%nodes(1:nv, c)) = mass(cells%nodes(1:nv, c)) + corner_share
        end if
      end if
    end do
    if (allocated(model%nodes%added_mass)) mass(1:model%nodes%n) = mass(1:model%nodes%n) + &
                                                                   model%nodes%added_mass
  end subroutine lumped_mass

  !> Area (2D, x-y plane) or volume (3D) of a simplex, unsigned.
  pure real(wp) function simplex_measure(dim, xc)
    integer, intent(in) :: dim                  !< 2 or 3
    real(wp), intent(in) :: xc(:,:)             !< (3, dim+1) corner coordinates
    if (dim == 2) then
      simplex_measure = 0.5_wp*abs((xc(1, 2) - xc(1, 1))*(xc(2, 3) - xc(2, 1)) - &
                                   (xc(2, 2) - xc(2, 1))*(xc(1, 3) - xc(1, 1)))
    else
      simplex_measure = abs(dot_product(cross(xc(:, 2) - xc(:, 1), xc(:, 3) - xc(:, 1)), &
                                        xc(:, 4) - xc(:, 1)))/6.0_wp
    end if
  end function simplex_measure

end module mefem_lumped_mass
