!> mefem main program (placeholder until the driver lands).
program mefem
  use mefem_comm, only: comm_init
  use mefem_errors, only: say, terminate
  implicit none
  call comm_init()
  call say('mefem')
  call terminate(0)
end program mefem
