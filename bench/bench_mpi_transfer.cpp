// MPI transfer time between two ranks on this machine, for the MPI executor's cost model
// (docs/benchmarks.md §8): half the round trip of messages the size of a step's blocks of sigma
// points. Run under mpirun with 2 ranks; prints a Markdown table, then the latency (8 B) and the
// bandwidth of the largest message.
#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <vector>

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size != 2) {
    if (rank == 0) std::fprintf(stderr, "bench_mpi_transfer: run with mpirun -np 2\n");
    MPI_Finalize();
    return 2;
  }
  // 8 B to 62 MB: the latency, then the UKF's blocks (2,791 rows x 1,396 columns at 2 ranks).
  const std::vector<long> sizes = {8, 1024, 65536, 1 << 20, 8 << 20, 31 << 20, 62 << 20};
  std::vector<char> buffer(static_cast<size_t>(sizes.back()), 1);
  std::vector<double> x, y;  // bytes and one-way seconds of the messages >= 1 MB
  if (rank == 0) std::printf("| bytes | one way, median of 9 (ms) | MB/s |\n|---:|---:|---:|\n");
  for (long bytes : sizes) {
    std::vector<double> times;
    for (int repeat = 0; repeat < 10; ++repeat) {
      MPI_Barrier(MPI_COMM_WORLD);
      const double start = MPI_Wtime();
      if (rank == 0) {
        MPI_Send(buffer.data(), static_cast<int>(bytes), MPI_BYTE, 1, 0, MPI_COMM_WORLD);
        MPI_Recv(buffer.data(), static_cast<int>(bytes), MPI_BYTE, 1, 0, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE);
      } else {
        MPI_Recv(buffer.data(), static_cast<int>(bytes), MPI_BYTE, 0, 0, MPI_COMM_WORLD,
                 MPI_STATUS_IGNORE);
        MPI_Send(buffer.data(), static_cast<int>(bytes), MPI_BYTE, 0, 0, MPI_COMM_WORLD);
      }
      if (repeat > 0) times.push_back((MPI_Wtime() - start) / 2);  // the first warms up
    }
    std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
    const double t = times[times.size() / 2];
    if (rank == 0)
      std::printf("| %ld | %.4f | %.0f |\n", bytes, 1e3 * t, 1e-6 * static_cast<double>(bytes) / t);
    if (bytes >= (1 << 20)) {
      x.push_back(static_cast<double>(bytes));
      y.push_back(t);
    }
    if (bytes == 8 && rank == 0) std::printf("latency (8 B): %.2f us\n", 1e6 * t);
  }
  if (rank == 0)
    std::printf("bandwidth (%ld B): %.3g GB/s\n", sizes.back(), 1e-9 * x.back() / y.back());
  MPI_Finalize();
  return 0;
}
